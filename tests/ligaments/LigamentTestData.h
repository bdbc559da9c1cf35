// Helpers of the ligaments tests: the shared data directory and a synthetic icosphere surface.
#pragma once
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim::test {

// BCASSIM_DATA, else <source>/../shared/data; empty when neither exists.
inline std::string ligamentDataDir() {
  if (const char* env = std::getenv("BCASSIM_DATA"); env && std::filesystem::is_directory(env)) {
    return env;
  }
  const std::string dir = std::string(BCASSIM_SOURCE_DIR) + "/../shared/data";
  return std::filesystem::is_directory(dir + "/livers") ? dir : std::string();
}

// Outward-oriented icosphere of `radius` (m) centred at the origin (the library's generator).
inline TriMesh makeIcosphere(double radius, int levels) {
  return makeIcosphereSurface(radius, levels);
}

}  // namespace bcassim::test
