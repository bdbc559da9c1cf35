#include "bcassim/atlas/CurveStatistics.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "bcassim/Error.h"
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

double medianOf(std::vector<double> v) {
  const size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
  const double upper = v[h];
  if (v.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h)));
}

Eigen::Vector3d meanOf(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const auto& p : pts) m += p;
  return m / static_cast<double>(pts.size());
}

double spreadOf(const std::vector<Eigen::Vector3d>& pts) {
  const Eigen::Vector3d m = meanOf(pts);
  double s = 0.0;
  for (const auto& p : pts) s += (p - m).squaredNorm();
  return std::sqrt(s / static_cast<double>(pts.size()));
}
}  // namespace

std::vector<int> hampelInliers(const std::vector<Eigen::Vector3d>& pts, double k) {
  if (!(k > 0.0)) throw InputError(fmt::format("Hampel identifier: k must be positive, got {}", k));
  std::vector<int> keep(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) keep[i] = static_cast<int>(i);
  if (pts.size() < 3) return keep;
  const Eigen::Vector3d med = geometricMedian(pts, meanOf(pts), spreadOf(pts));
  std::vector<double> d(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) d[i] = (pts[i] - med).norm();
  const double limit = k * 1.4826 * medianOf(d);
  std::vector<int> inliers;
  for (size_t i = 0; i < pts.size(); ++i)
    if (d[i] <= limit) inliers.push_back(static_cast<int>(i));
  return inliers.empty() ? keep : inliers;  // k < 0.68 can reject every point: keep them all
}

std::vector<PlaneStatistics> curveStatistics(const std::vector<Eigen::MatrixX3d>& curves,
                                             const CuttingPlaneFamily& planes, CurveCentre centre,
                                             double outlierMads) {
  if (centre == CurveCentre::Trimmed && !(outlierMads > 0.0)) {
    throw InputError(fmt::format(
        "curve statistics: outlier threshold must be positive, got {} MADs", outlierMads));
  }
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
    if (centre == CurveCentre::Trimmed) {
      std::vector<Eigen::Vector3d> inliers;
      for (int i : hampelInliers(pts, outlierMads)) inliers.push_back(pts[static_cast<size_t>(i)]);
      pts.swap(inliers);
    }
    s.kept = static_cast<int>(pts.size());
    for (const auto& p : pts) s.mean += p;
    s.mean /= s.kept;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& p : pts) cov += (p - s.mean) * (p - s.mean).transpose();
    cov /= s.kept;
    s.sigma = std::sqrt(std::max(0.0, cov.trace()));
    if (s.kept >= 2) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
      s.spread = eig.eigenvectors().col(2);
      if (centre == CurveCentre::Median) s.mean = geometricMedian(pts, s.mean, s.sigma);
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace bcassim
