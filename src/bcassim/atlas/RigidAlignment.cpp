#include "bcassim/atlas/RigidAlignment.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/mesh/PointSetAlignment.h"

namespace bcassim {

RigidTransform procrustes(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q) {
  return kabschFit(P, Q);
}

namespace {
// The curve of both surfaces as the ICP sees it: the source curve's vertices, each drawn to its
// closest point on the target curve's segments (a few hundred of each: searched directly).
struct IcpCurve {
  Eigen::MatrixX3d points;  // source curve vertices (source frame)
  Eigen::MatrixX3d a, b;    // target segments' ends
  double weight = 0.0;      // of the curve's mean squared distance, the surface's being 1

  IcpCurve() = default;
  IcpCurve(const TriMesh& source, const TriMesh& target, const CurvePair& pair, double w)
      : weight(w) {
    const auto check = [](const Eigen::MatrixX2i& edges, const TriMesh& m, const char* which) {
      if (edges.size() > 0 && (edges.minCoeff() < 0 || edges.maxCoeff() >= m.V.rows())) {
        throw InputError(fmt::format(
            "rigid alignment: the {} curve names vertices {}..{}, its surface has 0..{}", which,
            edges.minCoeff(), edges.maxCoeff(), m.V.rows() - 1));
      }
    };
    check(pair.source, source, "source");
    check(pair.target, target, "target");
    std::vector<int> ids(pair.source.data(), pair.source.data() + pair.source.size());
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    points.resize(static_cast<Eigen::Index>(ids.size()), 3);
    for (size_t k = 0; k < ids.size(); ++k)
      points.row(static_cast<Eigen::Index>(k)) = source.V.row(ids[k]);
    a.resize(pair.target.rows(), 3);
    b.resize(pair.target.rows(), 3);
    for (Eigen::Index e = 0; e < pair.target.rows(); ++e) {
      a.row(e) = target.V.row(pair.target(e, 0));
      b.row(e) = target.V.row(pair.target(e, 1));
    }
  }
  bool active() const { return weight > 0.0 && points.rows() > 0 && a.rows() > 0; }

  Eigen::RowVector3d closest(const Eigen::RowVector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    Eigen::RowVector3d out = a.row(0);
    for (Eigen::Index e = 0; e < a.rows(); ++e) {
      const Eigen::RowVector3d q =
          closestPointOnSegment(p.transpose(), a.row(e).transpose(), b.row(e).transpose())
              .transpose();
      const double dist2 = (p - q).squaredNorm();
      if (dist2 < best) {
        best = dist2;
        out = q;
      }
    }
    return out;
  }
};

// ICP from `start`; returns the transform and writes the last RMS distance: of the surface, or
// with a curve, sqrt((surface MSD + w curve MSD) / (1 + w)).
RigidTransform icp(const TriMesh& source, const SurfaceLocator& locator, RigidTransform total,
                   const IcpOptions& options, double* rmsOut, const IcpCurve& curve = {}) {
  double previousRms = std::numeric_limits<double>::infinity();
  const Eigen::Index ns = source.V.rows();
  const Eigen::Index nc = curve.active() ? curve.points.rows() : 0;
  Eigen::MatrixX3d moved(ns + nc, 3), closest(ns + nc, 3);
  Eigen::VectorXd weights(ns + nc);
  weights.head(ns).setConstant(1.0 / static_cast<double>(ns));
  if (nc > 0) weights.tail(nc).setConstant(curve.weight / static_cast<double>(nc));
  const double totalWeight = weights.sum();
  for (int it = 0; it < options.maxIterations; ++it) {
    moved.topRows(ns) = total.apply(source.V);
    if (nc > 0) moved.bottomRows(nc) = total.apply(curve.points);
    double sum2 = 0.0;
    for (Eigen::Index i = 0; i < ns; ++i) {
      const SurfacePoint sp = locator.closest(moved.row(i).transpose());
      closest.row(i) = sp.point.transpose();
      sum2 += weights(i) * sp.distance * sp.distance;
    }
    if (nc > 0) {
      Eigen::VectorXd d2(nc);
      for (Eigen::Index i = ns; i < ns + nc; ++i) {
        closest.row(i) = curve.closest(moved.row(i));
        d2(i - ns) = (moved.row(i) - closest.row(i)).squaredNorm();
      }
      const auto kept = std::max<Eigen::Index>(
          1, static_cast<Eigen::Index>(std::ceil(kCurveKeptFraction * static_cast<double>(nc))));
      std::vector<double> sorted(d2.data(), d2.data() + nc);
      std::nth_element(sorted.begin(), sorted.begin() + (kept - 1), sorted.end());
      const double limit = sorted[static_cast<size_t>(kept - 1)];
      Eigen::Index used = 0;
      for (Eigen::Index k = 0; k < nc; ++k) used += d2(k) <= limit ? 1 : 0;
      for (Eigen::Index k = 0; k < nc; ++k) {
        weights(ns + k) = d2(k) <= limit ? curve.weight / static_cast<double>(used) : 0.0;
        sum2 += weights(ns + k) * d2(k);
      }
    }
    const double rms = std::sqrt(sum2 / totalWeight);
    if (rmsOut) *rmsOut = rms;
    if (std::abs(previousRms - rms) < options.tolerance) break;
    previousRms = rms;
    const RigidTransform step =
        nc > 0 ? kabschFit(moved, closest, weights) : procrustes(moved, closest);
    total.rotation = step.rotation * total.rotation;
    total.translation = step.rotation * total.translation + step.translation;
  }
  return total;
}

// Start of ICP: rotation R about the source centroid, then centroids matched.
RigidTransform start(const TriMesh& source, const TriMesh& target, const Eigen::Matrix3d& R) {
  RigidTransform t;
  t.rotation = R;
  t.translation =
      (target.V.colwise().mean().transpose() - R * source.V.colwise().mean().transpose());
  return t;
}
}  // namespace

RigidTransform alignRigidly(const TriMesh& source, const TriMesh& target,
                            const IcpOptions& options) {
  if (source.V.rows() < 3) throw InputError("rigid alignment: source has fewer than 3 vertices");
  const SurfaceLocator locator(target);
  return icp(source, locator, start(source, target, Eigen::Matrix3d::Identity()), options, nullptr);
}

double rotationAngleDegrees(const Eigen::Matrix3d& R) {
  const double c = std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

RigidTransform alignRigidlyMultiStart(const TriMesh& source, const TriMesh& target,
                                      const IcpOptions& options, int probeIterations,
                                      double* rmsOut, double maxRotationDegrees,
                                      MultiStartReport* report, const CurvePair* curves,
                                      double curveWeight) {
  if (source.V.rows() < 3) throw InputError("rigid alignment: source has fewer than 3 vertices");
  if (!(curveWeight >= 0.0) || !std::isfinite(curveWeight)) {
    throw InputError(
        fmt::format("rigid alignment: curve weight must be >= 0, got {}", curveWeight));
  }
  const SurfaceLocator locator(target);
  const IcpCurve curve =
      curves && curves->present() ? IcpCurve(source, target, *curves, curveWeight) : IcpCurve();
  // The 24 proper rotations among signed permutation matrices, identity first.
  std::vector<Eigen::Matrix3d> rotations;
  const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {1, 0, 2}, {0, 2, 1}, {2, 1, 0}};
  for (const auto& p : perms) {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
      for (int r = 0; r < 3; ++r) R(r, p[r]) = (signs >> r) & 1 ? -1.0 : 1.0;
      if (R.determinant() > 0.0) rotations.push_back(R);
    }
  }
  IcpOptions probe = options;
  probe.maxIterations = std::max(1, probeIterations);
  // The best start overall and the best within the allowed rotation, after the probes.
  double bestRms = std::numeric_limits<double>::infinity();
  double plausibleRms = std::numeric_limits<double>::infinity();
  RigidTransform best, plausible;
  std::vector<std::pair<double, RigidTransform>> allowed;  // every probe within the limit
  for (const Eigen::Matrix3d& R : rotations) {
    double rms = std::numeric_limits<double>::infinity();
    const RigidTransform t = icp(source, locator, start(source, target, R), probe, &rms, curve);
    if (rms < bestRms * (1.0 - 1e-9)) {
      bestRms = rms;
      best = t;
    }
    if (rotationAngleDegrees(t.rotation) <= maxRotationDegrees) {
      allowed.emplace_back(rms, t);
      if (rms < plausibleRms * (1.0 - 1e-9)) {
        plausibleRms = rms;
        plausible = t;
      }
    }
  }
  // No start stays within the limit: the best fit, unflagged.
  const bool restricted = std::isfinite(plausibleRms) && plausibleRms > bestRms;
  MultiStartReport r;
  r.withCurve = curve.active();
  RigidTransform out = icp(source, locator, restricted ? plausible : best, options, &r.rms, curve);
  if (restricted) {
    // The refused start refined too: one ahead after the probe iterations may end behind
    // (LiTS-9 onto a three-liver template: 165.6 deg led the probes, then ended at RMS 11.2 mm
    // against 9.3 mm for 54.7 deg). Only a fit still clearly better is reported as refused.
    double refusedRms = 0.0;
    const RigidTransform refused = icp(source, locator, best, options, &refusedRms, curve);
    if (refusedRms < 0.99 * r.rms) {  // by 1 %: a symmetric shape fits its turned copies alike
      r.rejected = true;
      r.rejectedRms = refusedRms;
      r.rejectedRotationDegrees = rotationAngleDegrees(refused.rotation);
    }
  }
  // Rival poses: probes that ended far from the chosen one's pose, refined (at most three, best
  // first). One that fits within 3 % makes the pose ambiguous, said with both fits and how well
  // each carries the source's signed principal axes onto the target's. The choice is not changed:
  // on the shared livers onto LiTS-0 three poses were ambiguous, each rival fitting a little
  // better by RMS and by the axes, and each would have put the transferred curve farther from
  // the expert's (+6.6, +9.8, +10.4 mm).
  if (std::isfinite(plausibleRms)) {
    constexpr double kExactFit = 1e-9;  // m: fits closer than this are alike whatever their ratio
    const RigidTransform& chosenProbe = restricted ? plausible : best;
    std::sort(allowed.begin(), allowed.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::optional<SignedAxes> sa, ta;  // found when a rival is, not on every alignment
    std::vector<Eigen::Matrix3d> seen{out.rotation};
    int refined = 0;
    for (const auto& [probeRms, t] : allowed) {
      if (refined == 3 || probeRms > 1.1 * plausibleRms + kExactFit) break;
      if (rotationAngleDegrees(t.rotation * chosenProbe.rotation.transpose()) < kRivalPoseDegrees)
        continue;
      ++refined;
      double rivalRms = 0.0;
      const RigidTransform rival = icp(source, locator, t, options, &rivalRms, curve);
      const bool distinct = std::all_of(seen.begin(), seen.end(), [&](const Eigen::Matrix3d& R) {
        return rotationAngleDegrees(rival.rotation * R.transpose()) >= kRivalPoseDegrees;
      });
      if (!distinct || rotationAngleDegrees(rival.rotation) > maxRotationDegrees ||
          rivalRms > 1.03 * r.rms + kExactFit) {
        continue;
      }
      seen.push_back(rival.rotation);
      if (r.ambiguous && rivalRms >= r.rivalRms) continue;  // report the closest rival
      r.ambiguous = true;
      r.rivalRms = rivalRms;
      r.rivalApartDegrees = rotationAngleDegrees(rival.rotation * out.rotation.transpose());
      if (!sa) {
        sa = signedAxes(source);
        ta = signedAxes(target);
      }
      r.axesAgreement = axesAgreement(*sa, *ta, out.rotation);
      r.rivalAxesAgreement = axesAgreement(*sa, *ta, rival.rotation);
    }
  }
  r.rotationDegrees = rotationAngleDegrees(out.rotation);
  if (rmsOut) *rmsOut = r.rms;
  if (report) *report = r;
  return out;
}

std::vector<std::string> poseDoubts(const MultiStartReport& r, double maxRotationDegrees) {
  std::vector<std::string> out;
  if (r.rejected) {
    out.push_back(fmt::format(
        "the best rigid fit turns it {:.0f} deg (RMS {:.1f} mm), implausible for livers in scanner "
        "axes; kept the best within {:.0f} deg: {:.0f} deg (RMS {:.1f} mm)",
        r.rejectedRotationDegrees, 1e3 * r.rejectedRms, maxRotationDegrees, r.rotationDegrees,
        1e3 * r.rms));
  }
  if (r.ambiguous) {
    out.push_back(fmt::format(
        "two poses {:.0f} deg apart fit alike (RMS {:.1f} mm kept, {:.1f} mm the rival; signed "
        "principal axes agreement {:.2f} kept, {:.2f} the rival): check the orientation",
        r.rivalApartDegrees, 1e3 * r.rms, 1e3 * r.rivalRms, r.axesAgreement, r.rivalAxesAgreement));
  }
  return out;
}

SignedAxes signedAxes(const TriMesh& m) {
  // Area-weighted face centres: the surface's own distribution, whatever its sampling.
  double area = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<std::pair<double, Eigen::Vector3d>> faces;
  faces.reserve(static_cast<size_t>(m.F.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p0 = m.V.row(m.F(f, 0)).transpose();
    const Eigen::Vector3d p1 = m.V.row(m.F(f, 1)).transpose();
    const Eigen::Vector3d p2 = m.V.row(m.F(f, 2)).transpose();
    const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    faces.emplace_back(a, (p0 + p1 + p2) / 3.0);
    area += a;
    mean += a * faces.back().second;
  }
  SignedAxes out;
  if (!(area > 0.0)) return out;
  mean /= area;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& [a, c] : faces) cov += a * (c - mean) * (c - mean).transpose();
  cov /= area;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d axis = eig.eigenvectors().col(2 - k);  // decreasing variance
    const double variance = eig.eigenvalues()(2 - k);
    double third = 0.0;
    for (const auto& [a, c] : faces) third += a * std::pow(axis.dot(c - mean), 3);
    third /= area;
    const double skew = variance > 0.0 ? third / std::pow(variance, 1.5) : 0.0;
    out.axes.col(k) = skew < 0.0 ? Eigen::Vector3d(-axis) : axis;
    out.skewness(k) = std::abs(skew);
  }
  return out;
}

double axesAgreement(const SignedAxes& source, const SignedAxes& target, const Eigen::Matrix3d& R) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double w = std::min(source.skewness(k), target.skewness(k));
    sum += w * (R * source.axes.col(k)).dot(target.axes.col(k));
  }
  return sum;
}

namespace {
double surfaceArea(const TriMesh& m) {
  double a = 0.0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p0 = m.V.row(m.F(f, 0)).transpose();
    const Eigen::Vector3d p1 = m.V.row(m.F(f, 1)).transpose();
    const Eigen::Vector3d p2 = m.V.row(m.F(f, 2)).transpose();
    a += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  return a;
}
}  // namespace

double areaMatchingScale(const TriMesh& source, const TriMesh& target) {
  const double as = surfaceArea(source), at = surfaceArea(target);
  if (!(as > 0.0) || !(at > 0.0)) {
    throw InputError(fmt::format("area-matching scale: surface areas {} and {} m^2", as, at));
  }
  return std::sqrt(at / as);
}

}  // namespace bcassim
