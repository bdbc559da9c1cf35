#include "bcassim/mesh/ClosestPoint.h"

#include <fmt/format.h>

#include <algorithm>

#include "bcassim/Error.h"

namespace bcassim {

// Ericson, Real-Time Collision Detection, 5.1.5: classify p against the Voronoi regions of the
// vertices, edges and face, so no square roots and no special cases beyond zero denominators.
Vec3 closestPointOnSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 - d3 > 0 ? d1 / (d1 - d3) : 0.0;
    return {1 - v, v, 0};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 - d6 > 0 ? d2 / (d2 - d6) : 0.0;
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    const double w = den > 0 ? (d4 - d3) / den : 0.0;
    return {0, 1 - w, w};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) return {1, 0, 0};  // zero-area triangle whose regions all failed: a corner
  const double v = vb / sum, w = vc / sum;
  return {1 - v - w, v, w};
}

SurfaceLocator::SurfaceLocator(const TriMesh& surface) {
  if (surface.F.rows() == 0)
    throw InputError("surface locator: surface has no faces; expected at least one triangle");
  corners_.resize(3 * static_cast<size_t>(surface.F.rows()));
  tree_ = AabbTree(copyCorners(surface));
}

void SurfaceLocator::refit(const TriMesh& surface) {
  if (3 * static_cast<size_t>(surface.F.rows()) != corners_.size())
    throw InputError(fmt::format("surface locator: refit with {} faces; it was built with {}",
                                 surface.F.rows(), corners_.size() / 3));
  tree_.refit(copyCorners(surface));
}

std::vector<AabbTree::Box> SurfaceLocator::copyCorners(const TriMesh& surface) {
  const Eigen::Index nf = surface.F.rows(), nv = surface.V.rows();
  std::vector<AabbTree::Box> boxes(static_cast<size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = surface.F(f, k);
      if (v < 0 || v >= nv)
        throw InputError(fmt::format(
            "surface locator: face {} refers to vertex {}; expected an index in [0, {})", f, v,
            nv));
      corners_[3 * f + k] = surface.V.row(v).transpose();
      boxes[static_cast<size_t>(f)].extend(corners_[3 * f + k]);
    }
  return boxes;
}

SurfacePoint SurfaceLocator::closest(const Vec3& p) const {
  double bestSq;
  Vec3 bestBary = Vec3::Zero();
  const int face = tree_.nearest(
      p,
      [&](int f, double bestSoFar) {
        const Vec3& a = corners_[3 * f];
        const Vec3& b = corners_[3 * f + 1];
        const Vec3& c = corners_[3 * f + 2];
        const Vec3 w = closestPointOnTriangle(p, a, b, c);
        const double d = (w(0) * a + w(1) * b + w(2) * c - p).squaredNorm();
        if (d < bestSoFar) bestBary = w;
        return d;
      },
      bestSq);
  SurfacePoint out;
  out.face = face;
  out.barycentric = bestBary;
  out.point = bestBary(0) * corners_[3 * face] + bestBary(1) * corners_[3 * face + 1] +
              bestBary(2) * corners_[3 * face + 2];
  out.distance = (out.point - p).norm();
  return out;
}

SurfacePoint closestPointOnSurface(const TriMesh& surface, const Vec3& p) {
  return SurfaceLocator(surface).closest(p);
}

}  // namespace bcassim
