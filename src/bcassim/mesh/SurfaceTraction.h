// Consistent nodal shares of a uniform traction on the part of a tet mesh's boundary surface that
// lies in a region: a load defined on the continuum surface, so the same load on any mesh of it.
#pragma once
#include <vector>

#include "bcassim/mesh/Region.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct SurfaceTractionShares {
  std::vector<int> nodes;      // sorted boundary nodes that carry part of the load
  std::vector<double> shares;  // integral of node's shape function over the loaded surface,
                               // divided by the loaded area: they sum to 1
  double area = 0;             // m^2, loaded area of the (polygonal) boundary surface
};

// Each boundary face is split into subdivisions^2 equal sub-triangles; one whose centroid lies in
// the region is loaded, its area shared among the face's three nodes by their shape functions at
// that centroid. Exact for faces wholly inside or outside the region (1/3 of the area per node);
// a face cut by the region's border is resolved to 1/subdivisions of its size. An
// IndexListRegion loads the faces whose three nodes it lists. Throws InputError when no boundary
// surface lies in the region, or for an ill-formed region.
SurfaceTractionShares surfaceTractionShares(const TetMesh& mesh, const Region& region,
                                            int subdivisions = 16);

}  // namespace bcassim
