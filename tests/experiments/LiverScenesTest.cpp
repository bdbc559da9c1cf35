// The liver experiment's scenes are built in code; the scene files it writes for the user must
// load (loadScene) into the very same scenes: mesh, materials, boundary conditions, loads,
// springs, points, solver, time and the assimilation settings.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "bcassim/experiments/liver/LiverScenario.h"
#include "bcassim/experiments/liver/LiverScenes.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/SmallLiverOptions.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

constexpr double kRelative = 1e-12;

// |a - b| within kRelative of the larger magnitude (exact for zeros).
::testing::AssertionResult close(double a, double b) {
  if (std::abs(a - b) <= kRelative * std::max(std::abs(a), std::abs(b)))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b;
}

template <typename A, typename B>
::testing::AssertionResult closeMatrix(const Eigen::MatrixBase<A>& a,
                                       const Eigen::MatrixBase<B>& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure()
           << a.rows() << "x" << a.cols() << " vs " << b.rows() << "x" << b.cols();
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= kRelative * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "max difference " << diff << " of " << scale;
}

void expectSamePoints(const MarkerSet& a, const MarkerSet& b, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].tet, b.points[i].tet) << i;
    EXPECT_TRUE(closeMatrix(a.points[i].weights, b.points[i].weights)) << i;
  }
  EXPECT_TRUE(closeMatrix(a.rest, b.rest));
}

void expectSameProfile(const TimeProfile& a, const TimeProfile& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_TRUE(close(a.period, b.period));
  EXPECT_TRUE(close(a.phase, b.phase));
}

void expectSameTracks(const TrackFrames& a, const TrackFrames& b) {
  ASSERT_EQ(a.frames.size(), b.frames.size());
  EXPECT_EQ(a.present, b.present);
  for (size_t k = 0; k < a.frames.size(); ++k)
    EXPECT_TRUE(closeMatrix(a.frames[k], b.frames[k])) << "frame " << k;
}

void expectSameAssimilation(const AssimilationSettings& a, const AssimilationSettings& b) {
  EXPECT_EQ(a.filter, b.filter);
  EXPECT_EQ(a.sigmaPoints, b.sigmaPoints);
  EXPECT_EQ(a.threads, b.threads);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.carryPositions, b.carryPositions);
  EXPECT_EQ(a.carryVelocities, b.carryVelocities);
  EXPECT_EQ(a.reuseFactorization, b.reuseFactorization);
  EXPECT_EQ(a.meanTangent, b.meanTangent);
  EXPECT_EQ(a.tangentRefreshEvery, b.tangentRefreshEvery);
  EXPECT_EQ(a.tangentInBackground, b.tangentInBackground);
  EXPECT_EQ(a.tangentBackgroundSteps, b.tangentBackgroundSteps);
  EXPECT_EQ(a.tangentSinglePrecision, b.tangentSinglePrecision);
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
  for (size_t i = 0; i < a.parameters.size(); ++i) {
    const EstimatedParameter &p = a.parameters[i], &q = b.parameters[i];
    SCOPED_TRACE(p.name);
    EXPECT_EQ(p.name, q.name);
    const auto* s = std::get_if<SpringCoefficientTarget>(&p.target);
    const auto* t = std::get_if<SpringCoefficientTarget>(&q.target);
    ASSERT_TRUE(s && t);
    EXPECT_EQ(s->group, t->group);
    EXPECT_EQ(s->coefficient, t->coefficient);
    EXPECT_TRUE(close(p.mean, q.mean));
    EXPECT_TRUE(close(p.stddev, q.stddev));
    EXPECT_EQ(p.transform.kind(), q.transform.kind());
    EXPECT_TRUE(close(p.transform.lower(), q.transform.lower()));
    EXPECT_TRUE(close(p.transform.upper(), q.transform.upper()));
    EXPECT_TRUE(close(p.randomWalkPerStep, q.randomWalkPerStep));
    EXPECT_EQ(p.truth.has_value(), q.truth.has_value());
  }
  EXPECT_TRUE(close(a.observations.noiseStddev, b.observations.noiseStddev));
  EXPECT_TRUE(close(a.observations.sigma, b.observations.sigma));
  EXPECT_EQ(a.observations.untilStep, b.observations.untilStep);
  EXPECT_EQ(a.observations.timeOffset, b.observations.timeOffset);
  expectSameTracks(a.observations.tracks, b.observations.tracks);
  ASSERT_EQ(a.validationTruth.has_value(), b.validationTruth.has_value());
  if (a.validationTruth) expectSameTracks(*a.validationTruth, *b.validationTruth);
}

// `loaded` (from the file) against `built` (in code).
void expectSameScene(const Scene& loaded, const Scene& built) {
  EXPECT_EQ(loaded.sourceFile, built.sourceFile);
  const MechanicalModel &a = loaded.model, &b = built.model;
  ASSERT_TRUE(closeMatrix(a.mesh->V, b.mesh->V));
  ASSERT_EQ(a.mesh->T, b.mesh->T);
  ASSERT_EQ(a.elasticity.numRegions(), b.elasticity.numRegions());
  EXPECT_STREQ(materialName(a.elasticity.material(0)), materialName(b.elasticity.material(0)));
  EXPECT_TRUE(close(a.mass.totalMass(), b.mass.totalMass()));
  EXPECT_EQ(a.mass.kind(), b.mass.kind());
  EXPECT_EQ(a.gravity, b.gravity);
  EXPECT_TRUE(close(a.rayleighMass, b.rayleighMass));
  EXPECT_TRUE(close(a.rayleighStiffness, b.rayleighStiffness));
  EXPECT_EQ(a.dirichlet.constrainedDofs(), b.dirichlet.constrainedDofs());

  ASSERT_EQ(a.loads.size(), b.loads.size());
  for (size_t i = 0; i < a.loads.size(); ++i) {
    SCOPED_TRACE("load " + std::to_string(i));
    EXPECT_EQ(a.loads[i].nodes, b.loads[i].nodes);
    EXPECT_EQ(a.loads[i].weights, b.loads[i].weights);
    EXPECT_TRUE(closeMatrix(a.loads[i].forcePerNode, b.loads[i].forcePerNode));
    expectSameProfile(a.loads[i].profile, b.loads[i].profile);
  }

  const auto &s = a.springs.springs(), &t = b.springs.springs();
  ASSERT_EQ(s.size(), t.size());
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s[i].tet, t[i].tet) << "spring " << i;
    EXPECT_EQ(s[i].group, t[i].group) << "spring " << i;
    EXPECT_TRUE(closeMatrix(s[i].weights, t[i].weights)) << "spring " << i;
    EXPECT_TRUE(closeMatrix(s[i].anchor, t[i].anchor)) << "spring " << i;
    EXPECT_TRUE(close(s[i].restLength, t[i].restLength)) << "spring " << i;
  }
  ASSERT_EQ(a.springs.numGroups(), b.springs.numGroups());
  for (int g = 0; g < a.springs.numGroups(); ++g) {
    const CubicSpringCoefficients &p = a.springs.coefficients(g), &q = b.springs.coefficients(g);
    EXPECT_TRUE(close(p.kAlpha, q.kAlpha)) << "group " << g;
    EXPECT_TRUE(close(p.kBeta, q.kBeta)) << "group " << g;
    EXPECT_TRUE(close(p.kGamma, q.kGamma)) << "group " << g;
    EXPECT_EQ(a.springs.cutTime(g), b.springs.cutTime(g)) << "group " << g;
  }

  // Materials, springs, loads and damping together: the same forces at a deformed state (10 µm
  // node by node: well below the smallest tet, so no element inverts; forces refuse that).
  Eigen::VectorXd x = a.restPositions();
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += 1e-5 * std::sin(0.7 * static_cast<double>(i));
  Eigen::VectorXd fa = Eigen::VectorXd::Zero(x.size()), fb = fa, ea = fa, eb = fa;
  a.internalForces(0.5, x, fa);
  b.internalForces(0.5, x, fb);
  EXPECT_TRUE(closeMatrix(fa, fb)) << "internal forces";
  a.externalForces(0.7, ea);
  b.externalForces(0.7, eb);
  EXPECT_TRUE(closeMatrix(ea, eb)) << "external forces";

  expectSamePoints(loaded.markers, built.markers, "markers");
  expectSamePoints(loaded.validation, built.validation, "validation points");
  expectSamePoints(loaded.hidden, built.hidden, "hidden points");

  EXPECT_EQ(loaded.integrator, built.integrator);
  EXPECT_EQ(loaded.dt(), built.dt());
  EXPECT_EQ(loaded.steps, built.steps);
  EXPECT_EQ(loaded.implicitEuler.newtonIterations, built.implicitEuler.newtonIterations);
  EXPECT_EQ(loaded.implicitEuler.newtonTolerance, built.implicitEuler.newtonTolerance);
  EXPECT_EQ(loaded.solver.type, built.solver.type);
  EXPECT_EQ(loaded.solver.policy.everyNMatrices, built.solver.policy.everyNMatrices);
  EXPECT_EQ(loaded.solver.policy.maxIterations, built.solver.policy.maxIterations);
  EXPECT_EQ(loaded.solver.policy.relTol, built.solver.policy.relTol);
  EXPECT_EQ(loaded.solver.policy.singlePrecision, built.solver.policy.singlePrecision);
  EXPECT_EQ(loaded.solver.policy.background, built.solver.policy.background);
  EXPECT_EQ(loaded.output.every, built.output.every);
  EXPECT_EQ(loaded.output.pvd, built.output.pvd);
  EXPECT_TRUE(built.variants.empty());
  ASSERT_EQ(loaded.assimilation.has_value(), built.assimilation.has_value());
  if (loaded.assimilation) expectSameAssimilation(*loaded.assimilation, *built.assimilation);
}

// Stand-in truth tracks on the scenes' time grid (rest positions drifting by 0.1 mm a step), so
// that estimate.yaml loads without running the truth.
void writeTruthTracks(const std::filesystem::path& dir, const Scene& scene) {
  for (const auto& [file, points] :
       {std::pair{"markers.csv", &scene.markers}, std::pair{"validation.csv", &scene.validation}}) {
    MarkerTrackWriter tracks((dir / "truth" / file).string());
    for (int k = 0; k <= scene.steps; ++k)
      tracks.write(k * scene.dt(), Eigen::MatrixX3d(points->rest.array() + 1e-4 * k));
  }
}

TEST(LiverScenes, WrittenFilesLoadIntoTheScenesBuiltInCode) {
  const auto dir = test::freshDir();
  LiverScenarioOptions o = test::smallLiverOptions();
  o.noise = 2e-5;  // below the filter's floor of 0.1 mm: sigma differs from noise_stddev
  const LiverScenario scenario = prepareLiverScenario(o, dir.string());
  ASSERT_TRUE(scenario.truthScene && scenario.estimateScene && scenario.baselineScene);
  EXPECT_EQ(scenario.truthScene->model.springs.numGroups(), 24);
  EXPECT_EQ(scenario.estimateScene->assimilation->parameters.size(), 3u);
  EXPECT_GT(scenario.baselineScene->model.dirichlet.constrainedDofs().size(),
            scenario.estimateScene->model.dirichlet.constrainedDofs().size());
  writeTruthTracks(dir, *scenario.estimateScene);

  {
    SCOPED_TRACE("truth.yaml");
    expectSameScene(loadScene((dir / "truth.yaml").string()), *scenario.truthScene);
  }
  {
    SCOPED_TRACE("estimate.yaml");
    expectSameScene(loadScene((dir / "estimate.yaml").string()),
                    withTruthTracks(*scenario.estimateScene, (dir / "truth").string()));
  }
  {
    SCOPED_TRACE("baseline.yaml");
    expectSameScene(loadScene((dir / "baseline.yaml").string()), *scenario.baselineScene);
  }
}

}  // namespace
}  // namespace bcassim
