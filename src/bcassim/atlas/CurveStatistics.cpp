#include "bcassim/atlas/CurveStatistics.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "bcassim/atlas/PlaneIntersection.h"

namespace bcassim {

namespace {
// Weiszfeld iterations from the mean; stops when a step moves less than 1e-12 of the spread.
Eigen::Vector3d geometricMedian(const std::vector<Eigen::Vector3d>& pts, Eigen::Vector3d m,
                                double scale) {
  for (int it = 0; it < 200; ++it) {
    Eigen::Vector3d num = Eigen::Vector3d::Zero();
    double den = 0.0;
    for (const auto& p : pts) {
      const double d = (p - m).norm();
      if (d < 1e-15 * (scale + 1e-300)) return p;  // the median sits on a point
      num += p / d;
      den += 1.0 / d;
    }
    const Eigen::Vector3d next = num / den;
    const double step = (next - m).norm();
    m = next;
    if (step <= 1e-12 * scale) break;
  }
  return m;
}
}  // namespace

std::vector<PlaneStatistics> curveStatistics(const std::vector<Eigen::MatrixX3d>& curves,
                                             const CuttingPlaneFamily& planes, CurveCentre centre) {
  std::vector<PlaneStatistics> out;
  out.reserve(planes.planes.size());
  for (const CuttingPlane& plane : planes.planes) {
    std::vector<std::vector<PlaneHit>> hits;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    int nHits = 0;
    for (const Eigen::MatrixX3d& c : curves) {
      hits.push_back(intersectPolyline(c, plane));
      for (const PlaneHit& h : hits.back()) centroid += h.point;
      nHits += static_cast<int>(hits.back().size());
    }
    PlaneStatistics s;
    if (nHits == 0) {
      out.push_back(s);
      continue;
    }
    centroid /= nHits;
    std::vector<Eigen::Vector3d> pts;
    for (const auto& h : hits) {
      if (h.empty()) continue;
      double best = std::numeric_limits<double>::infinity();
      Eigen::Vector3d pick = h.front().point;
      for (const PlaneHit& x : h) {
        const double d = (x.point - centroid).squaredNorm();
        if (d < best) {
          best = d;
          pick = x.point;
        }
      }
      pts.push_back(pick);
    }
    s.count = static_cast<int>(pts.size());
    for (const auto& p : pts) s.mean += p;
    s.mean /= s.count;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& p : pts) cov += (p - s.mean) * (p - s.mean).transpose();
    cov /= s.count;
    s.sigma = std::sqrt(std::max(0.0, cov.trace()));
    if (s.count >= 2) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
      s.spread = eig.eigenvectors().col(2);
      if (centre == CurveCentre::Median) s.mean = geometricMedian(pts, s.mean, s.sigma);
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace bcassim
