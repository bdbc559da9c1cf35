// Points spread uniformly by area over the part of a triangle surface that faces a direction:
// what a camera looking against that direction sees of an organ (self-occlusion ignored).
#pragma once
#include <cstdint>

#include "bcassim/Types.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct SurfaceSamples {
  Eigen::MatrixX3d points;    // #samples by 3, on the surface, m
  double areaFraction = 0.0;  // of the surface the faces they lie on cover
};

// `count` points uniformly by area on the faces of `surface` most turned towards `view` (a
// direction from the organ to the camera), taken in that order until `coverage` of the area.
// Deterministic for a seed. Throws InputError for a coverage outside (0, 1], count < 1 or a
// surface without triangles.
SurfaceSamples sampleVisibleSurface(const TriMesh& surface, const Vec3& view, double coverage,
                                    int count, std::uint64_t seed);

}  // namespace bcassim
