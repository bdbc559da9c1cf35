// Geometric and index selections of nodes and tets (fixed boundaries, loaded patches, material
// zones). Coordinates in metres, compared against rest positions; boxes and spheres include their
// boundary.
#pragma once
#include <optional>
#include <variant>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct BoxRegion {
  Vec3 min, max;  // corners, metres; min <= max componentwise
};

struct SphereRegion {
  Vec3 center;    // metres
  double radius;  // metres, >= 0
};

// Points x with (x - point) . normal >= 0; normal need not be unit length.
struct HalfSpaceRegion {
  Vec3 point, normal;
};

// Explicit ids: node ids for selectNodes, tet ids for selectTets.
struct IndexListRegion {
  std::vector<int> indices;
};

// Boundary-surface nodes inside `within`, optionally only those whose rest outward vertex normal
// is within maxAngleDeg of `direction` (need not be unit length).
struct SurfacePatchRegion {
  std::variant<BoxRegion, SphereRegion> within;
  std::optional<Vec3> direction;
  double maxAngleDeg = 90.0;
};

using Region =
    std::variant<BoxRegion, SphereRegion, HalfSpaceRegion, IndexListRegion, SurfacePatchRegion>;

// Sorted, unique node ids of `mesh` in `region` (positions mesh.V). An empty result is returned as
// such; the caller decides whether that is an error. Throws InputError for an ill-formed region
// (min > max, negative radius, zero normal or direction, index out of range).
std::vector<int> selectNodes(const TetMesh& mesh, const Region& region);

// Sorted, unique tet ids whose centroid lies in the region; IndexListRegion lists tet ids; for a
// SurfacePatchRegion, the tets owning a boundary face whose three nodes are all in the patch.
// Throws as selectNodes.
std::vector<int> selectTets(const TetMesh& mesh, const Region& region);

// Whether rest point x of the boundary surface, on a face with unit outward rest normal
// faceNormal, lies in the region (a SurfacePatchRegion tests the face normal against its
// direction). An IndexListRegion holds no point: it selects ids, so this throws std::logic_error.
// Throws InputError for an ill-formed region, as selectNodes.
bool containsSurfacePoint(const Region& region, const Vec3& x, const Vec3& faceNormal);

}  // namespace bcassim
