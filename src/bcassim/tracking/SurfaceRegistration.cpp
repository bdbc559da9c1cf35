#include "bcassim/tracking/SurfaceRegistration.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/tracking/PointCloudUnits.h"

namespace bcassim {

std::vector<Eigen::Matrix3d> defaultStartRotations() {
  std::vector<Vec3> axes;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) axes.push_back(sign * Vec3::Unit(axis));
  for (const double x : {1.0, -1.0})
    for (const double y : {1.0, -1.0})
      for (const double z : {1.0, -1.0}) axes.push_back(Vec3(x, y, z).normalized());
  std::vector<Eigen::Matrix3d> rotations{Eigen::Matrix3d::Identity()};
  for (const double degrees : {25.0, 50.0, 90.0})
    for (const Vec3& axis : axes)
      rotations.push_back(
          Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis).toRotationMatrix());
  for (int axis = 0; axis < 3; ++axis)
    rotations.push_back(Eigen::AngleAxisd(std::numbers::pi, Vec3::Unit(axis)).toRotationMatrix());
  return rotations;
}

namespace {

void requireInputs(const Eigen::MatrixX3d& points, const TriMesh& surface,
                   const SurfaceRegistrationOptions& o) {
  if (points.rows() < 6)
    throw InputError(
        fmt::format("point cloud of {} points; expected at least 6 to register it "
                    "rigidly to a surface",
                    points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (!points.row(i).allFinite())
      throw InputError(
          fmt::format("point cloud point {} has a non-finite coordinate; expected "
                      "finite coordinates (m)",
                      i));
  if (surface.F.rows() == 0)
    throw InputError("surface without triangles; expected a triangle surface to register to");
  if (!(o.keepFraction > 0.0 && o.keepFraction <= 1.0))
    throw InputError(
        fmt::format("registration keepFraction {}; expected a fraction in (0, 1]", o.keepFraction));
  if (!(o.medianFactor >= 0.0) || !(o.minThreshold >= 0.0) || !(o.tolerance >= 0.0))
    throw InputError(
        fmt::format("registration medianFactor {}, minThreshold {} m, tolerance {} m; "
                    "expected numbers >= 0",
                    o.medianFactor, o.minThreshold, o.tolerance));
  if (o.startRotations.empty())
    throw InputError("registration without start rotations; expected at least one (the identity)");
  if (o.probeIterations < 1 || o.maxIterations < 1 || o.probePoints < 6 || o.refinedStarts < 1)
    throw InputError(
        fmt::format("registration probeIterations {}, maxIterations {}, probePoints {}, "
                    "refinedStarts {}; expected at least 1, 1, 6 and 1",
                    o.probeIterations, o.maxIterations, o.probePoints, o.refinedStarts));
}

// The surface with what point-to-plane ICP needs of it: the AABB tree, and normals that vary
// continuously over the surface (area-weighted vertex normals, interpolated), so that the
// tangent plane does not jump when a noisy point's closest point crosses an edge.
struct PlaneTarget {
  SurfaceLocator locator;
  Eigen::MatrixX3i faces;
  Eigen::MatrixX3d vertexNormals;

  explicit PlaneTarget(const TriMesh& s)
      : locator(s), faces(s.F), vertexNormals(Eigen::MatrixX3d::Zero(s.V.rows(), 3)) {
    for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
      const Vec3 a = s.V.row(s.F(f, 0)), b = s.V.row(s.F(f, 1)), c = s.V.row(s.F(f, 2));
      const Vec3 n = (b - a).cross(c - a);  // twice the area times the unit normal
      for (int k = 0; k < 3; ++k) vertexNormals.row(s.F(f, k)) += n.transpose();
    }
    for (Eigen::Index v = 0; v < vertexNormals.rows(); ++v) {
      const double length = vertexNormals.row(v).norm();
      if (length > 0.0) vertexNormals.row(v) /= length;
    }
  }

  // Unit normal at a closest point (zero where the surface has none, e.g. a needle face).
  Vec3 normalAt(const SurfacePoint& sp) const {
    Vec3 n = Vec3::Zero();
    for (int k = 0; k < 3; ++k)
      n += sp.barycentric[k] * vertexNormals.row(faces(sp.face, k)).transpose();
    const double length = n.norm();
    return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
  }
};

// Closest points of the moved cloud and which of them the trimming keeps.
struct Pairs {
  Eigen::MatrixX3d closest, normals;
  Eigen::VectorXd distances;
  std::vector<int> kept;
  double median = 0.0;  // over all points, m
  double rms = 0.0;     // over the kept points, m
  double limit = 0.0;   // m, the trimming's distance limit (infinity: none)
};

double medianOf(std::vector<double> values) {
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  double m = values[mid];
  if (values.size() % 2 == 0)
    m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + mid));
  return m;
}

Pairs findPairs(const Eigen::MatrixX3d& moved, const PlaneTarget& target,
                const SurfaceRegistrationOptions& o) {
  const Eigen::Index n = moved.rows();
  Pairs p;
  p.closest.resize(n, 3);
  p.normals.resize(n, 3);
  p.distances.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const SurfacePoint sp = target.locator.closest(moved.row(i).transpose());
    p.closest.row(i) = sp.point.transpose();
    p.normals.row(i) = target.normalAt(sp).transpose();
    p.distances[i] = sp.distance;
  }
  p.median = medianOf(std::vector<double>(p.distances.begin(), p.distances.end()));
  const double limit = o.medianFactor > 0.0 ? std::max(o.medianFactor * p.median, o.minThreshold)
                                            : std::numeric_limits<double>::infinity();
  p.limit = limit;
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return p.distances[a] < p.distances[b]; });
  const auto maxKept = static_cast<size_t>(std::max(1.0, std::floor(o.keepFraction * n)));
  double sum2 = 0.0;
  for (int i : order) {
    if (p.kept.size() >= maxKept || p.distances[i] > limit) break;
    p.kept.push_back(i);
    sum2 += p.distances[i] * p.distances[i];
  }
  p.rms = p.kept.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(p.kept.size()));
  return p;
}

// One Gauss-Newton step of point-to-plane ICP: the small rotation w (about the kept points'
// centroid c) and translation t minimising sum ((m_i - q_i).n_i + ((m_i - c) x n_i).w + n_i.t)^2.
struct PlaneStep {
  Vec3 w = Vec3::Zero(), t = Vec3::Zero(), c = Vec3::Zero();
  double radius = 0.0;  // m, of the kept points about c

  // The step scaled by alpha, as a rigid transform, and the largest distance it moves a kept
  // point (m).
  RigidTransform scaled(double alpha) const {
    RigidTransform step;
    const double angle = alpha * w.norm();
    if (angle > 0.0) step.rotation = Eigen::AngleAxisd(angle, w.normalized()).toRotationMatrix();
    step.translation = c - step.rotation * c + alpha * t;
    return step;
  }
  double largestMove(double alpha) const { return alpha * (w.norm() * radius + t.norm()); }
};

PlaneStep pointToPlaneStep(const Eigen::MatrixX3d& moved, const Pairs& pairs) {
  PlaneStep s;
  for (int i : pairs.kept) s.c += moved.row(i).transpose();
  s.c /= static_cast<double>(pairs.kept.size());
  for (int i : pairs.kept) s.radius = std::max(s.radius, (moved.row(i).transpose() - s.c).norm());
  const double scale = s.radius > 0.0 ? s.radius : 1.0;  // rotation unknowns in metres: balanced
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (int i : pairs.kept) {
    const Vec3 m = moved.row(i).transpose(), q = pairs.closest.row(i).transpose();
    const Vec3 n = pairs.normals.row(i).transpose();
    Eigen::Matrix<double, 6, 1> J;
    J << (m - s.c).cross(n) / scale, n;
    A.selfadjointView<Eigen::Lower>().rankUpdate(J);
    b -= J * (m - q).dot(n);
  }
  Eigen::Matrix<double, 6, 6> normal = A.selfadjointView<Eigen::Lower>();
  // A tiny ridge keeps directions the view cannot see (e.g. sliding along a flat patch) at rest.
  normal.diagonal().array() += 1e-12 * normal.trace() + 1e-300;
  const Eigen::Matrix<double, 6, 1> x = normal.ldlt().solve(b);
  s.w = x.head<3>() / scale;
  s.t = x.tail<3>();
  return s;
}

// How well a pose fits, comparable between poses: the mean over the closest keepFraction of the
// points of min(d, cap)^2, with one cap for all the poses compared (medianFactor times the
// smallest of their medians, at least minThreshold; none when medianFactor is 0). A pose is not
// rewarded for leaving points out: a dozen tackers fitted 54 degrees off with 4 of 14 points
// trimmed had a smaller median, and a larger score, than the true pose with all of them.
double cappedScore(const Eigen::VectorXd& distances, double cap, double keepFraction) {
  std::vector<double> d2(static_cast<size_t>(distances.size()));
  for (Eigen::Index i = 0; i < distances.size(); ++i)
    d2[static_cast<size_t>(i)] = std::pow(std::min(distances[i], cap), 2);
  std::sort(d2.begin(), d2.end());
  const auto kept =
      static_cast<size_t>(std::max(1.0, std::floor(keepFraction * static_cast<double>(d2.size()))));
  double sum = 0.0;
  for (size_t i = 0; i < kept; ++i) sum += d2[i];
  return sum / static_cast<double>(kept);
}

struct IcpRun {
  RigidTransform transform;
  Pairs pairs;  // at `transform`
  int iterations = 0;
  bool converged = false;
  double lastMove = 0.0;  // m, the last iteration's largest move of a point
};

// ICP with a backtracking line search: the Gauss-Newton step is halved until the trimmed, capped
// squared distance (cappedScore at the iteration's trimming limit) does not grow. The tangent
// planes are a linearisation: with a dozen points on a smooth surface a full step can slide the
// pose far along the surface and back again on the next iteration (LiTS-11's tackers: still
// 2.4 mm per iteration after 100). No descent left within the tolerance is convergence.
IcpRun runIcp(const Eigen::MatrixX3d& points, const PlaneTarget& target, RigidTransform transform,
              int maxIterations, const SurfaceRegistrationOptions& o) {
  IcpRun run;
  Eigen::MatrixX3d moved = transform.apply(points), movedBefore = moved;
  run.pairs = findPairs(moved, target, o);
  for (int it = 0; it < maxIterations; ++it) {
    if (run.pairs.kept.size() < 3) break;
    const PlaneStep step = pointToPlaneStep(moved, run.pairs);
    const double current = cappedScore(run.pairs.distances, run.pairs.limit, o.keepFraction);
    double alpha = 1.0;
    bool descended = false;
    RigidTransform next;
    Eigen::MatrixX3d movedNow;
    Pairs pairsNow;
    for (int halving = 0; halving <= 30 && step.largestMove(alpha) > o.tolerance; ++halving) {
      next = compose(step.scaled(alpha), transform);
      movedNow = next.apply(points);
      pairsNow = findPairs(movedNow, target, o);
      if (cappedScore(pairsNow.distances, run.pairs.limit, o.keepFraction) <= current) {
        descended = true;
        break;
      }
      alpha *= 0.5;
    }
    run.iterations = it + 1;
    if (!descended) {  // the step, however short, no longer lowers the distance: stationary
      run.converged = true;
      run.lastMove = 0.0;
      break;
    }
    transform = next;
    // A point at the trimming limit can drop out and in again on alternate iterations: back
    // within the tolerance of the pose two iterations ago is converged too.
    const double cycle = (movedNow - movedBefore).rowwise().norm().maxCoeff();
    movedBefore = std::move(moved);
    moved = std::move(movedNow);
    run.pairs = std::move(pairsNow);
    run.lastMove = step.largestMove(alpha);
    if (run.lastMove <= o.tolerance || (it > 0 && cycle <= o.tolerance)) {
      run.converged = true;
      break;
    }
  }
  run.transform = transform;
  return run;
}

}  // namespace

SurfaceRegistration registerPointsToSurface(const Eigen::MatrixX3d& points, const TriMesh& surface,
                                            const SurfaceRegistrationOptions& options) {
  requireInputs(points, surface, options);
  requireMatchingUnits(points, surface);
  const PlaneTarget target(surface);
  const Vec3 centre = options.initial.apply(points).colwise().mean().transpose();
  std::vector<RigidTransform> starts;
  for (const Eigen::Matrix3d& R : options.startRotations) {
    RigidTransform about;  // rotation R about the centre of the initially moved points
    about.rotation = R;
    about.translation = centre - R * centre;
    starts.push_back(compose(about, options.initial));
  }
  // Probes on evenly spaced rows: a large cloud's probes cost what probePoints' cost.
  const Eigen::Index probeCount = std::min<Eigen::Index>(points.rows(), options.probePoints);
  Eigen::MatrixX3d probePoints(probeCount, 3);
  for (Eigen::Index i = 0; i < probeCount; ++i)
    probePoints.row(i) = points.row(i * points.rows() / probeCount);
  // The starts are independent (the locator's queries are const): probed in parallel, chosen
  // in order afterwards, so the result does not depend on the threads.
  std::vector<IcpRun> probes(starts.size());
  tbb::parallel_for(size_t{0}, starts.size(), [&](size_t k) {
    probes[k] = runIcp(probePoints, target, starts[k], options.probeIterations, options);
  });
  // One cap for the runs compared (cappedScore).
  auto scoresOf = [&](const std::vector<IcpRun>& runs) {
    double smallestMedian = std::numeric_limits<double>::infinity();
    for (const IcpRun& r : runs) smallestMedian = std::min(smallestMedian, r.pairs.median);
    const double cap = options.medianFactor > 0.0
                           ? std::max(options.medianFactor * smallestMedian, options.minThreshold)
                           : std::numeric_limits<double>::infinity();
    std::vector<double> scores(runs.size());
    for (size_t k = 0; k < runs.size(); ++k)
      scores[k] = cappedScore(runs[k].pairs.distances, cap, options.keepFraction);
    return scores;
  };
  const std::vector<double> probeScores = scoresOf(probes);
  std::vector<int> order(starts.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return probeScores[a] < probeScores[b]; });
  order.resize(std::min<size_t>(order.size(), options.refinedStarts));
  std::vector<IcpRun> converged(order.size());
  tbb::parallel_for(size_t{0}, order.size(), [&](size_t r) {
    converged[r] =
        runIcp(probePoints, target, probes[order[r]].transform, options.maxIterations, options);
  });
  const std::vector<double> scores = scoresOf(converged);
  size_t deepest = 0;
  for (size_t r = 1; r < order.size(); ++r)
    if (scores[r] < scores[deepest] || (scores[r] == scores[deepest] && order[r] < order[deepest]))
      deepest = r;
  const int best = order[deepest];
  const IcpRun refined =
      probeCount == points.rows()
          ? std::move(converged[deepest])
          : runIcp(points, target, converged[deepest].transform, options.maxIterations, options);
  SurfaceRegistration result;
  result.transform = refined.transform;
  result.rms = refined.pairs.rms;
  result.overlap =
      static_cast<double>(refined.pairs.kept.size()) / static_cast<double>(points.rows());
  result.iterations = refined.iterations;
  result.converged = refined.converged;
  result.lastMove = refined.lastMove;
  result.start = best;
  return result;
}

}  // namespace bcassim
