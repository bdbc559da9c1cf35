// Embeds points (markers, surface vertices of another mesh) in a tetrahedral mesh by barycentric
// coordinates, so they follow the mesh as it deforms. Points outside map to the nearest tet.
// Positions in metres.
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/AabbTree.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

struct MappedPoint {
  int tet = -1;           // containing (or nearest) tet
  Vec4 weights;           // barycentric weights of the tet's 4 nodes, sum 1
  bool inside = false;    // inside a tet up to 1e-10 in barycentric coordinates
  double distance = 0.0;  // metres from the point to the mesh; 0 when inside
};

// Point-location index over a tet mesh (AABB tree over the tets plus a SurfaceLocator over the
// boundary for points outside). Build once, query many; queries allocate nothing and may run
// concurrently.
class TetLocator {
 public:
  // Copies what it needs from `mesh` (rest positions). Throws InputError for an empty mesh or a
  // node index out of range.
  explicit TetLocator(const TetMesh& mesh);

  // A point inside maps to a containing tet with its barycentric weights (all >= -1e-10); a point
  // outside to the closest point of the nearest tet, whose weights are all >= 0.
  MappedPoint locate(const Vec3& p) const;

 private:
  struct TetFrame {
    Mat3 inverseEdges;  // inverse of [b-a, c-a, d-a]
    Vec3 origin;        // a
    bool valid;         // false for a flat tet, which cannot contain points
  };
  std::vector<TetFrame> frames_;
  AabbTree tree_;
  double boxTolerance_ = 0.0;  // metres, slack on tet boxes matching the weight tolerance
  SurfaceLocator boundary_;
  std::vector<int> faceTet_;                   // boundary face -> owning tet
  std::vector<std::array<int, 3>> faceLocal_;  // boundary face corner -> local node in its tet
};

// points: #P by 3, metres. Result in the order of the rows. Parallel over points.
std::vector<MappedPoint> mapPoints(const TetMesh& mesh, const Eigen::MatrixX3d& points);
std::vector<MappedPoint> mapPoints(const TetLocator& locator, const Eigen::MatrixX3d& points);

// Position of a mapped point for node positions `positions` (3N node-major, metres). Throws
// InputError when positions has the wrong size.
Vec3 interpolate(const MappedPoint& mp, const TetMesh& mesh, const Eigen::VectorXd& positions);

// Position of a mapped point at rest (mesh.V).
Vec3 interpolate(const MappedPoint& mp, const TetMesh& mesh);

}  // namespace bcassim
