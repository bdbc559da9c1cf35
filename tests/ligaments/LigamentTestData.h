// Helper of the ligaments and atlas tests: a synthetic icosphere surface (the shared data
// directory: support/SharedData.h).
#pragma once
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim::test {

// Outward-oriented icosphere of `radius` (m) centred at the origin (the library's generator).
inline TriMesh makeIcosphere(double radius, int levels) {
  return makeIcosphereSurface(radius, levels);
}

}  // namespace bcassim::test
