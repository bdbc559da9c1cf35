// Closest point on a triangle surface: single-triangle and segment kernels and SurfaceLocator, an
// AABB-tree index built once and queried many times (marker projection, surface distances). Metres.
#pragma once
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mesh/AabbTree.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct SurfacePoint {
  int face = -1;     // index into the TriMesh's F
  Vec3 barycentric;  // weights of the face's three vertices, each >= 0, summing to 1
  Vec3 point;        // closest point, metres
  double distance;   // |query - point|, metres
};

// Barycentric weights (of a, b, c) of the point of triangle abc closest to p. Degenerate triangles
// are handled: the result is still a point of the triangle.
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The point of segment ab closest to p (a when the segment has zero length).
Vec3 closestPointOnSegment(const Vec3& p, const Vec3& a, const Vec3& b);

class SurfaceLocator {
 public:
  // Empty locator, to be assigned later; closest() needs a built one.
  SurfaceLocator() = default;
  // Copies the triangle geometry of `surface` (#V by 3 positions, #F by 3 indices), so the
  // TriMesh may go away afterwards. Throws InputError when the surface has no faces or a face
  // index is out of range.
  explicit SurfaceLocator(const TriMesh& surface);

  // The same faces at new vertex positions (`surface` has the faces it was built with): the
  // corners are copied again and the tree refitted, not rebuilt (AabbTree::refit), so that a
  // surface that deforms step after step is searched again at O(n). Throws InputError when the
  // face count differs or a face index is out of range.
  void refit(const TriMesh& surface);

  // Closest point of the surface to p; ties go to the lower face index found first.
  SurfacePoint closest(const Vec3& p) const;

  int numFaces() const { return static_cast<int>(corners_.size() / 3); }

 private:
  // Copies the faces' corners (corners_ sized already) and returns each face's box.
  std::vector<AabbTree::Box> copyCorners(const TriMesh& surface);

  std::vector<Vec3> corners_;  // 3 per face, face-major, for cache-friendly leaf tests
  AabbTree tree_;
};

// One-off query: builds a SurfaceLocator and discards it. For many queries keep a SurfaceLocator.
SurfacePoint closestPointOnSurface(const TriMesh& surface, const Vec3& p);

}  // namespace bcassim
