// Rigid registration without correspondences (tracking/SurfaceRegistration): the default search
// (46 starts probed on <= 500 points, the best 4 to convergence, a line search) against the single
// probe refined of the first version (13 starts, 10 iterations each on all points, one refined),
// on a 30 % partial view of the built-in liver phantom's surface, the wedge of the tests (1,500
// points with 1 mm noise, 20 degrees / 10 cm off) and on 14 tacker-like points (0.3 mm noise).
// Times only: which poses each finds is what tests/tracking/TestSurfaceRegistration.cpp asserts.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <numbers>
#include <random>

#include "bcassim/experiments/liver/LiverPhantom.h"
#include "bcassim/mesh/VisibleSurface.h"
#include "bcassim/tracking/SurfaceRegistration.h"

namespace bcassim {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

struct Case {
  TriMesh surface;
  Eigen::MatrixX3d cloud;
  RigidTransform guess;
};

Case makeCase(int points, double noise) {
  Case c;
  c.surface = makeLiverPhantom().surface;
  const SurfaceSamples view = sampleVisibleSurface(c.surface, Vec3(0.2, 1.0, 0.6), 0.3, points, 3);
  RigidTransform truth;
  truth.rotation =
      Eigen::AngleAxisd(20 * kDegree, Vec3(0.3, 1.0, -0.4).normalized()).toRotationMatrix();
  truth.translation = Vec3(0.06, -0.06, 0.05);
  c.cloud = truth.inverse().apply(view.points);
  std::mt19937 rng(9);
  std::normal_distribution<double> gauss(0.0, noise);
  for (Eigen::Index i = 0; i < c.cloud.rows(); ++i)
    c.cloud.row(i) += Eigen::RowVector3d(gauss(rng), gauss(rng), gauss(rng));
  c.guess.translation = (view.points.colwise().mean() - c.cloud.colwise().mean()).transpose();
  return c;
}

SurfaceRegistrationOptions singleProbe() {
  SurfaceRegistrationOptions o;
  o.startRotations = {Eigen::Matrix3d::Identity()};
  for (const double degrees : {45.0, 90.0})
    for (int axis = 0; axis < 3; ++axis)
      for (const double sign : {1.0, -1.0})
        o.startRotations.push_back(
            Eigen::AngleAxisd(sign * degrees * kDegree, Vec3::Unit(axis)).toRotationMatrix());
  o.probeIterations = 10;
  o.probePoints = 1 << 30;
  o.refinedStarts = 1;
  return o;
}

void run(benchmark::State& state, int points, double noise, bool single, double medianFactor) {
  const Case c = makeCase(points, noise);
  SurfaceRegistrationOptions o = single ? singleProbe() : SurfaceRegistrationOptions{};
  o.initial = c.guess;
  o.medianFactor = medianFactor;
  for (auto _ : state) benchmark::DoNotOptimize(registerPointsToSurface(c.cloud, c.surface, o));
}

void BM_PartialView1500_Default(benchmark::State& s) { run(s, 1500, 1e-3, false, 3.0); }
void BM_PartialView1500_SingleProbe(benchmark::State& s) { run(s, 1500, 1e-3, true, 3.0); }
void BM_Tackers14_Default(benchmark::State& s) { run(s, 14, 3e-4, false, 0.0); }
void BM_Tackers14_SingleProbe(benchmark::State& s) { run(s, 14, 3e-4, true, 0.0); }

BENCHMARK(BM_PartialView1500_Default)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PartialView1500_SingleProbe)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Tackers14_Default)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Tackers14_SingleProbe)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace bcassim

BENCHMARK_MAIN();
