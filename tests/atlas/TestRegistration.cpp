// Registration (eq. 4.7): exact objective gradient in the momenta, recovery of a known LDDMM
// deformation, control-point grid; optionally two real livers.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/ControlPoints.h"
#include "bcassim/atlas/Registration.h"
#include "bcassim/atlas/RegistrationObjective.h"
#include "bcassim/atlas/VarifoldDistance.h"
#include "bcassim/io/SurfaceReader.h"
#include "support/SharedData.h"

namespace bcassim {
namespace {

TEST(ControlPoints, RegularGridCentredOnBoundingBox) {
  Eigen::MatrixX3d V(2, 3);
  V << 0.0, 0.0, 0.0, 0.1, 0.05, 0.005;
  const Eigen::MatrixX3d q = regularGridControlPoints(V, 0.02);
  EXPECT_EQ(q.rows(), 6 * 3 * 1);
  EXPECT_NEAR(q.col(0).minCoeff(), 0.0, 1e-15);
  EXPECT_NEAR(q.col(0).maxCoeff(), 0.1, 1e-15);
  EXPECT_NEAR(q.col(1).minCoeff(), 0.005, 1e-15);  // 0.05 holds 2 spacings: 5 mm margins
  EXPECT_NEAR(q.col(2).maxCoeff(), 0.0025, 1e-15);
  EXPECT_THROW(regularGridControlPoints(V, 0.0), InputError);
}

void checkObjectiveGradient(ShootingIntegrator integrator) {
  const TriMesh source = test::makeIcosphere(0.05, 1);
  const TriMesh target = test::makeIcosphere(0.045, 2, {0.005, 0.0, -0.004});
  const VarifoldDistance distance(target, 0.02);
  const GeodesicShooting shooting(0.04, {6, integrator});
  const Eigen::MatrixX3d q0 = regularGridControlPoints(source.V, 0.04);
  const RegistrationObjective objective(source, distance, shooting, q0, 1.0 / (0.02 * 0.02));
  const Eigen::MatrixX3d a0 = test::randomMatrix(q0.rows(), 0.003, 21);
  Eigen::MatrixX3d g;
  const RegistrationTerms t = objective.evaluate(a0, &g);
  EXPECT_NEAR(t.total, objective.evaluate(a0).total, 1e-14 * t.total);
  EXPECT_GT(t.regularity, 0.0);
  const double h = 1e-7;
  double maxErr = 0.0;
  for (Eigen::Index i = 0; i < a0.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixX3d p = a0, m = a0;
      p(i, c) += h;
      m(i, c) -= h;
      const double fd = (objective.evaluate(p).total - objective.evaluate(m).total) / (2 * h);
      maxErr = std::max(maxErr, std::abs(fd - g(i, c)));
    }
  }
  EXPECT_LT(maxErr, 1e-6 * g.cwiseAbs().maxCoeff());
}

TEST(RegistrationObjective, GradientMatchesFiniteDifferencesEuler) {
  checkObjectiveGradient(ShootingIntegrator::Euler);
}
TEST(RegistrationObjective, GradientMatchesFiniteDifferencesRk2) {
  checkObjectiveGradient(ShootingIntegrator::Rk2);
}

TEST(Registration, RecoversKnownDeformation) {
  const TriMesh source = test::makeIcosphere(0.05, 2);
  RegistrationOptions o;
  o.sigmaV = 0.03;
  o.sigmaW = 0.015;
  const Eigen::MatrixX3d q0 = regularGridControlPoints(source.V, o.sigmaV);
  const GeodesicShooting shooting(o.sigmaV, o.shooting);
  TriMesh target = source;
  target.V = shooting.flow(q0, test::randomMatrix(q0.rows(), 0.003, 31), source.V);
  const double moved = (target.V - source.V).rowwise().norm().maxCoeff();
  EXPECT_GT(moved, 0.008);
  const RegistrationResult r = registerSurface(source, target, o);
  EXPECT_LE(r.data, 0.05 * r.initialData) << r.iterations << " iterations";
  // The data term is measured on the returned vertices.
  EXPECT_NEAR(VarifoldDistance(target, o.sigmaW).value(r.deformedVertices, source.F), r.data,
              1e-12 * r.initialData);
}

TEST(Registration, TwoRealLivers) {
  const std::filesystem::path dir = test::sharedPath("livers");
  std::vector<std::filesystem::path> files;
  if (!dir.empty()) {
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".obj") files.push_back(e.path());
  }
  if (files.size() < 2) GTEST_SKIP() << "no liver surfaces under " << dir;
  std::sort(files.begin(), files.end());
  TriMesh a = readSurface(files[0].string()), b = readSurface(files[1].string());
  a.V *= 1e-3;  // mm to m
  b.V *= 1e-3;
  // Centre both: rigid alignment is not this test's subject.
  a.V.rowwise() -= a.V.colwise().mean();
  b.V.rowwise() -= b.V.colwise().mean();
  RegistrationOptions o;
  o.sigmaV = 0.03;
  o.sigmaW = 0.015;
  o.lbfgs.maxIterations = 6;  // a few seconds; the full registration converges further
  const auto t0 = std::chrono::steady_clock::now();
  const RegistrationResult r = registerSurface(a, b, o);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RecordProperty("seconds", std::to_string(seconds));
  std::printf(
      "livers %s -> %s: %ld/%ld faces, %ld control points, %d iterations, %.2f s, "
      "D %.3e -> %.3e\n",
      files[0].filename().c_str(), files[1].filename().c_str(), long(a.F.rows()), long(b.F.rows()),
      long(r.controlPoints.rows()), r.iterations, seconds, r.initialData, r.data);
  EXPECT_LT(r.data, 0.5 * r.initialData);
}

}  // namespace
}  // namespace bcassim
