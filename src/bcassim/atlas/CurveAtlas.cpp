#include "bcassim/atlas/CurveAtlas.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {

CurveAtlas buildCurveAtlas(const TriMesh& templ, const std::vector<Eigen::MatrixX3d>& curves,
                           const CuttingPlaneFamily& planes, int minCount, CurveCentre centre,
                           double outlierMads) {
  if (templ.F.rows() == 0) throw InputError("curve atlas: the template has no faces");
  const std::vector<PlaneStatistics> stats = curveStatistics(curves, planes, centre, outlierMads);
  const SurfaceLocator locator(templ);
  CurveAtlas a;
  a.planes = planes;
  std::vector<Eigen::Vector3d> means, lows, highs;
  std::vector<double> sigmas;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < stats.size(); ++k) {
    const PlaneStatistics& s = stats[k];
    if (s.count < std::max(1, minCount)) continue;
    const SurfacePoint sp = locator.closest(s.mean);
    // Band direction: in the plane and tangent to the surface at the projected mean.
    const Eigen::Vector3d v0 = templ.V.row(templ.F(sp.face, 0)).transpose();
    const Eigen::Vector3d v1 = templ.V.row(templ.F(sp.face, 1)).transpose();
    const Eigen::Vector3d v2 = templ.V.row(templ.F(sp.face, 2)).transpose();
    const Eigen::Vector3d faceNormal = (v1 - v0).cross(v2 - v0);
    Eigen::Vector3d b = planes.planes[k].normal.cross(faceNormal);
    if (b.norm() < 1e-12 * faceNormal.norm() || faceNormal.norm() == 0.0) b = s.spread;
    if (b.norm() > 0.0) b.normalize();
    // Consistent sides along the curve: lower and upper do not swap from plane to plane.
    const Eigen::Vector3d ref = previous.norm() > 0.0 ? previous : planes.axis;
    if (b.dot(ref) < 0.0) b = -b;
    if (b.norm() > 0.0) previous = b;
    a.plane.push_back(static_cast<int>(k));
    a.count.push_back(s.count);
    sigmas.push_back(s.sigma);
    means.push_back(sp.point);
    lows.push_back(sp.point - s.sigma * b);
    highs.push_back(sp.point + s.sigma * b);
  }
  if (means.empty()) {
    throw InputError(fmt::format("curve atlas: no cutting plane is crossed by {} of the {} curves",
                                 minCount, curves.size()));
  }
  const auto n = static_cast<Eigen::Index>(means.size());
  Eigen::MatrixX3d M(n, 3), L(n, 3), H(n, 3);
  a.sigma.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    M.row(i) = means[i].transpose();
    L.row(i) = lows[i].transpose();
    H.row(i) = highs[i].transpose();
    a.sigma(i) = sigmas[i];
  }
  a.mean = SurfaceAttachment(templ, M);
  a.lower = SurfaceAttachment(templ, L);
  a.upper = SurfaceAttachment(templ, H);
  return a;
}

CarriedCurve carryCurve(const CurveAtlas& atlas, const Eigen::MatrixX3d& V) {
  CarriedCurve c;
  c.mean = atlas.mean.positions(V);
  c.lower = atlas.lower.positions(V);
  c.upper = atlas.upper.positions(V);
  c.sigma = 0.5 * ((c.upper - c.mean).rowwise().norm() + (c.mean - c.lower).rowwise().norm());
  return c;
}

CarriedCurve projectOnto(const CarriedCurve& curve, const TriMesh& surface) {
  const SurfaceLocator locator(surface);
  auto project = [&](const Eigen::MatrixX3d& P) {
    Eigen::MatrixX3d Q(P.rows(), 3);
    for (Eigen::Index i = 0; i < P.rows(); ++i)
      Q.row(i) = locator.closest(P.row(i).transpose()).point.transpose();
    return Q;
  };
  CarriedCurve c;
  c.mean = project(curve.mean);
  c.lower = project(curve.lower);
  c.upper = project(curve.upper);
  c.sigma = 0.5 * ((c.upper - c.mean).rowwise().norm() + (c.mean - c.lower).rowwise().norm());
  return c;
}

}  // namespace bcassim
