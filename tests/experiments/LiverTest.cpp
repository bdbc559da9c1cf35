// The liver experiment: uncertainty of embedded points, ligament springs read from a scene, and
// a small end-to-end run on the built-in phantom (estimation beats the fixed-ligament baseline;
// observations shrink the tumours' uncertainty; a random walk on bounded stiffnesses widens it in
// the free run).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "bcassim/coupling/FreeRunModelError.h"
#include "bcassim/coupling/InnovationModelError.h"
#include "bcassim/coupling/PointUncertainty.h"
#include "bcassim/experiments/liver/LiverPhantom.h"
#include "bcassim/experiments/liver/LiverPipeline.h"
#include "bcassim/experiments/liver/LiverScenes.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/mechanics/TimeProfile.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::writeText;

TEST(PointUncertainty, LinearMapOfTheStateCovariance) {
  const TetMesh mesh = makeBoxMesh(Vec3(1, 1, 1), 1, 1, 1);
  const Eigen::Index n = 3 * mesh.numNodes();
  Eigen::MatrixXd S = Eigen::MatrixXd::Random(n + 5, 4);  // 5 extra rows: parameters
  MappedPoint p;
  p.tet = 2;
  p.weights << 0.1, 0.2, 0.3, 0.4;
  const std::vector<PointUncertainty> u = pointUncertainty(mesh, {p}, S);
  // Direct: H (3 x n) with the weights on the tet's nodes, covariance H S S^T H^T.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, n + 5);
  for (int k = 0; k < 4; ++k)
    H.block(0, 3 * mesh.T(p.tet, k), 3, 3) += p.weights(k) * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d C = H * S * S.transpose() * H.transpose();
  EXPECT_LT((u[0].covariance - C).norm(), 1e-12 * C.norm());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(u[0].sigma(c), std::sqrt(C(c, c)), 1e-12);
  const double lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues().maxCoeff();
  EXPECT_NEAR(u[0].radius95, std::sqrt(7.814727903251178 * lambda), 1e-12);
  EXPECT_THROW(pointUncertainty(mesh, {p}, S.topRows(n - 1)), InputError);
}

// Innovations of variance sigma^2 + q (observation noise plus a model error the filter does not
// know): the estimate recovers q; none before any observation; never negative.
TEST(InnovationModelError, RecoversTheExcessVarianceOfTheInnovations) {
  const double sigma = 5e-4, q = 4e-7;  // 0.5 mm noise, 0.63 mm model error per coordinate
  InnovationModelError e;
  EXPECT_EQ(e.variance(sigma), 0.0);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> d(0.0, std::sqrt(sigma * sigma + q));
  for (int step = 0; step < 2000; ++step) {
    Eigen::VectorXd innovation(42);
    for (Eigen::Index i = 0; i < innovation.size(); ++i) innovation(i) = d(rng);
    e.add(innovation.norm(), innovation.size());
    e.add(0.0, 0);  // a step without observations changes nothing
  }
  // 84,000 squares: the relative standard error of their mean is sqrt(2 / 84000) = 0.5 %, i.e.
  // 4.7e-9 m^2 on sigma^2 + q = 6.5e-7; allow 5 standard errors.
  EXPECT_NEAR(e.variance(sigma), q, 2.4e-8);
  EXPECT_EQ(e.variance(1.0), 0.0);
}

// Markers displaced 2 mm from rest on every coordinate while observed: a model error of q per
// coordinate is a relative error rho^2 = q / (2 mm)^2. A hidden point then moving 3 mm and 4 mm
// in two free steps (a 7 mm path, even though it ends 5 mm away) gains rho^2 (7 mm)^2 / 3; a
// still one gains nothing; an observed step starts again from nothing.
TEST(FreeRunModelError, GrowsWithThePathMovedSinceTheLastObservation) {
  const double q = 1e-6;
  FreeRunModelError f;
  const Eigen::MatrixX3d markers = Eigen::MatrixX3d::Constant(4, 3, 2e-3);
  Eigen::MatrixX3d hidden = Eigen::MatrixX3d::Zero(2, 3);
  EXPECT_EQ(f.relativeVariance(q), 0.0);
  for (int k = 0; k < 3; ++k) f.add(true, markers, hidden);
  EXPECT_DOUBLE_EQ(f.relativeVariance(q), q / 4e-6);
  EXPECT_EQ(f.growth(q), Eigen::VectorXd::Zero(2));
  hidden(0, 0) = 3e-3;
  f.add(false, markers, hidden);
  hidden(0, 1) = 4e-3;
  f.add(false, markers, hidden);
  const Eigen::VectorXd g = f.growth(q);
  EXPECT_NEAR(g(0), q / 4e-6 * 49e-6 / 3, 1e-18);
  EXPECT_EQ(g(1), 0.0);
  f.add(true, markers, hidden);
  EXPECT_EQ(f.growth(q), Eigen::VectorXd::Zero(2));
}

TEST(TimeProfile, HalfSinePushesOneWayOnly) {
  TimeProfile p;
  p.kind = TimeProfile::Kind::HalfSine;
  p.period = 4.0;
  EXPECT_NEAR(p.value(1.0), 1.0, 1e-12);
  EXPECT_NEAR(p.value(3.0), 0.0, 1e-12);
  EXPECT_NEAR(p.value(0.5), std::sin(M_PI / 4), 1e-12);
}

TEST(SceneLigament, CurveExtrudedIntoGroupedSpringsAlongTheNormal) {
  const auto dir = freshDir();
  // A curve across the top face (z = 0.04) of a 0.1 x 0.04 x 0.04 m box.
  writeText(dir / "curve.csv", "x,y,z\n0.01,0.02,0.04\n0.05,0.02,0.04\n0.09,0.02,0.04\n");
  const Scene scene = loadSceneFromString(
      "mesh: {generator: box, size: [0.1, 0.04, 0.04], cells: [10, 4, 4]}\n"
      "springs:\n"
      "  groups: [{coefficients: [1, 0, 2]}, {coefficients: [1, 0, 3]}, {coefficients: [1, 0, "
      "4]}]\n"
      "  ligament: {curve: curve.csv, length: 0.03, spacing: 0.01, layers: 2, layer_offset: "
      "0.005}\n",
      "ligament.yaml", dir.string());
  const CubicSpringSet& springs = scene.model.springs;
  ASSERT_EQ(springs.springs().size(), 16u);  // 2 layers x round(0.08 m / 0.01 m)
  std::vector<int> perGroup(3, 0);
  const Eigen::VectorXd x = scene.model.restPositions();
  for (size_t s = 0; s < springs.springs().size(); ++s) {
    const CubicSpring& sp = springs.springs()[s];
    ++perGroup[sp.group];
    const Vec3 a = springs.attachment(*scene.model.mesh, x, s);
    EXPECT_NEAR(sp.restLength, 0.03, 1e-12);
    EXPECT_NEAR(a.z(), 0.04, 1e-9);                              // on the top face
    EXPECT_LT((sp.anchor - a - Vec3(0, 0, 0.03)).norm(), 1e-9);  // along the outward normal
  }
  for (int g = 0; g < 3; ++g) EXPECT_GT(perGroup[g], 0) << "group " << g;
  EXPECT_THROW(
      loadSceneFromString("mesh: {generator: box}\nsprings: {ligament: {curve: nope.csv}}\n",
                          "bad.yaml", dir.string()),
      InputError);
}

TEST(SceneLigament, ABandReadFromTwoCurvesHoldsTheLayersOnItsEdges) {
  const auto dir = freshDir();
  writeText(dir / "curve.csv", "x,y,z\n0.01,0.02,0.04\n0.05,0.02,0.04\n0.09,0.02,0.04\n");
  writeText(dir / "lower.csv", "x,y,z\n0.01,0.015,0.04\n0.05,0.01,0.04\n0.09,0.005,0.04\n");
  writeText(dir / "upper.csv", "x,y,z\n0.01,0.025,0.04\n0.05,0.03,0.04\n0.09,0.035,0.04\n");
  const std::string head =
      "mesh: {generator: box, size: [0.1, 0.04, 0.04], cells: [10, 4, 4]}\n"
      "springs:\n"
      "  groups: [{coefficients: [1, 0, 2]}]\n"
      "  ligament: {curve: curve.csv, spacing: 0.01, ";
  const Scene scene = loadSceneFromString(head + "band: {lower: lower.csv, upper: upper.csv}}\n",
                                          "band.yaml", dir.string());
  const CubicSpringSet& springs = scene.model.springs;
  ASSERT_EQ(springs.springs().size(), 16u);
  const Eigen::VectorXd x = scene.model.restPositions();
  for (size_t s = 0; s < springs.springs().size(); ++s) {
    const Vec3 a = springs.attachment(*scene.model.mesh, x, s);
    const double half = 0.005 + 0.01 * (a.x() - 0.01) / 0.08;  // the band widens along x
    EXPECT_NEAR(a.y(), s < 8 ? 0.02 - half : 0.02 + half, 1e-9) << s;
    EXPECT_NEAR(a.z(), 0.04, 1e-9);
  }
  writeText(dir / "short.csv", "x,y,z\n0.01,0.015,0.04\n0.09,0.005,0.04\n");
  auto errorOf = [&](const std::string& rest) {
    try {
      loadSceneFromString(head + rest, "band.yaml", dir.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(errorOf("band: {lower: short.csv, upper: upper.csv}}\n"),
            "band.yaml:4: springs.ligament.band.lower: 2 points, expected as many as the curve "
            "(3)");
  EXPECT_EQ(errorOf("layers: 1, band: {lower: lower.csv, upper: upper.csv}}\n"),
            "band.yaml:4: springs.ligament.band: expected 2 layers (the band's two edges), got 1");
  EXPECT_EQ(errorOf("band: {lower: lower.csv}}\n"),
            "band.yaml:4: springs.ligament.band.upper: cannot open '" + (dir / "").string() + "'");
}

TEST(LiverPhantom, LabelsAFalciformCurveAndARidge) {
  const LiverPhantom p = makeLiverPhantom();
  int falciform = 0, ridge = 0;
  for (int l : p.edges.labels) falciform += l == 2, ridge += l == 3;
  EXPECT_GT(falciform, 10);
  EXPECT_GT(ridge, 10);
  EXPECT_EQ(p.edges.labels.size(), p.edges.edges.size());
}

LiverScenarioOptions smallPhantom() {
  LiverScenarioOptions o;
  o.surface = kLiverPhantomName;
  o.coarseNodes = 1200;
  o.fineNodes = 2500;
  o.groups = 4;
  o.steps = 150;
  o.observedSteps = 150;
  o.dt = 0.02;
  o.threads = 2;
  return o;
}

// Mean 95 % radius of the tumours over the steps of hidden_points.csv after the first, m.
double meanRadius(const std::filesystem::path& csv) {
  const CsvTable t = readCsvTable(csv.string());
  double sum = 0;
  int n = 0;
  for (Eigen::Index r = 0; r < t.rows.rows(); ++r)
    if (t.rows(r, t.column("step")) > 0) sum += t.rows(r, t.column("radius95_m")), ++n;
  return n ? sum / n : NAN;
}

// Small-size thesis §5.1: the estimated springs bring the coarse model closer to the truth at
// the inner points than the ligament held fixed (the prior springs are reported, not asserted:
// on this small mesh they are already close).
TEST(LiverPipeline, SmallPhantomEstimationBeatsFixedBaseline) {
  const auto dir = freshDir();
  const LiverReport r = runLiverPipeline(smallPhantom(), dir.string());
  EXPECT_EQ(r.estimated.steps, 150);
  EXPECT_GT(r.maxDeformationMm, 2.0);
  EXPECT_LT(r.estimated.meanMm, r.fixed.meanMm);
  EXPECT_LT(r.estimated.maxMm, r.fixed.maxMm);
  // The tumours' radius with the model error seen in the innovations is far wider than the
  // parameters' alone and holds the true tumour most of the time.
  EXPECT_GT(r.finalTumourTotalRadius95Mm, 10 * r.finalTumourRadius95Mm);
  EXPECT_GT(r.tumourCoverage, 0.5);
  std::cout << "[ phantom ] tumour radius " << r.finalTumourTotalRadius95Mm << " mm, coverage "
            << r.tumourCoverage << "\n";
  for (const char* f : {"errors_over_time.csv", "summary.csv", "truth/hidden.csv",
                        "estimate/hidden_points.csv", "estimated/simulation.pvd"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
}

// The tumours' uncertainty comes from the parameters' (positions start known): observing the
// markers shrinks it below that of the same run predicting without observations.
TEST(LiverPipeline, ObservationsShrinkTumourUncertainty) {
  const auto dir = freshDir();
  LiverScenarioOptions o = smallPhantom();
  o.steps = 100;
  o.observedSteps = 100;
  prepareLiverScenario(o, (dir / "observed").string());
  o.observedSteps = 0;
  prepareLiverScenario(o, (dir / "blind").string());
  double radius[2];
  int i = 0;
  for (const char* run : {"observed", "blind"}) {
    const auto d = dir / run;
    runSimulation(loadScene((d / "truth.yaml").string()), (d / "truth").string());
    runAssimilation(loadScene((d / "estimate.yaml").string()), (d / "estimate").string());
    radius[i++] = meanRadius(d / "estimate" / "hidden_points.csv");
  }
  EXPECT_GT(radius[1], 0.0);
  EXPECT_LT(radius[0], radius[1]) << "observed " << radius[0] << " m, blind " << radius[1];
}

// The free run of one assimilation: per tumour, its 95 % radius (parameters only, and with the
// model error) at each step from the last observed one on, and how often the true tumour lies
// within the total radius, and the mean distance to it.
struct FreeRun {
  std::vector<std::vector<double>> radius, totalRadius;  // [tumour][step - observedSteps]
  int inside = 0, frames = 0;
  double meanErrorM = 0;
};

FreeRun freeRunOf(const std::filesystem::path& hiddenCsv, const std::filesystem::path& truthCsv,
                  int observedSteps) {
  const CsvTable t = readCsvTable(hiddenCsv.string());
  const MarkerTracks truth = readMarkerTracks(truthCsv.string());
  const int cs = t.column("step"), cp = t.column("point"), cx = t.column("x_m"),
            cr = t.column("radius95_m"), ct = t.column("radius95_total_m");
  FreeRun f;
  for (Eigen::Index r = 0; r < t.rows.rows(); ++r) {
    const int step = static_cast<int>(t.rows(r, cs));
    const auto point = static_cast<size_t>(t.rows(r, cp));
    if (step < observedSteps) continue;
    if (f.radius.size() <= point) f.radius.resize(point + 1), f.totalRadius.resize(point + 1);
    f.radius[point].push_back(t.rows(r, cr));
    f.totalRadius[point].push_back(t.rows(r, ct));
    if (step == observedSteps) continue;  // the free run proper: steps after the last observation
    const Vec3 predicted = t.rows.block<1, 3>(r, cx).transpose();
    const double error = (predicted - truth.frames.at(static_cast<size_t>(step))
                                          .row(static_cast<Eigen::Index>(point))
                                          .transpose())
                             .norm();
    f.meanErrorM += error;
    ++f.frames;
    if (error <= t.rows(r, ct)) ++f.inside;
  }
  if (f.frames) f.meanErrorM /= f.frames;
  return f;
}

// Every estimated mean of estimates.csv (step,time_s,parameter,mean,stddev; step 0 = prior).
std::vector<double> estimatedMeans(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> means;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string field;
    for (int i = 0; i < 4; ++i) std::getline(fields, field, ',');
    means.push_back(std::stod(field));
  }
  return means;
}

// Issue 15 point 2: with the stiffnesses bounded (bounded-log) and walking at random, the
// estimates never leave their bounds, the tumours' radius due to the parameters ends the free run
// wider than with constant stiffnesses, and the accuracy is that of the former set-up (log
// transform, constant stiffnesses) run beside it on the same truth, within 10 %. Once the
// observations stop, the total radius never shrinks (the model error grows with the path each
// tumour moves, FreeRunModelError) and holds the true tumour in at least 90 % of the free run's
// frames.
TEST(LiverPipeline, BoundedRandomWalkKeepsAccuracyAndWidensTheParametersRadius) {
  const auto dir = freshDir();
  LiverScenarioOptions o = smallPhantom();
  o.steps = 120;
  o.observedSteps = 70;
  o.stiffnessRandomWalk = 0.3;  // 30 % per sqrt(s)
  const LiverScenario scenario = prepareLiverScenario(o, dir.string());
  runSimulation(*scenario.truthScene, (dir / "truth").string());
  Scene walking = withTruthTracks(*scenario.estimateScene, (dir / "truth").string());
  Scene constant = walking;
  for (EstimatedParameter& p : constant.assimilation->parameters) {
    p.transform = ParameterTransform::exponential();
    p.randomWalkPerStep = 0;
  }
  const AssimilationResult withWalk = runAssimilation(walking, (dir / "walk").string());
  const AssimilationResult without = runAssimilation(constant, (dir / "constant").string());
  const FreeRun w =
      freeRunOf(dir / "walk" / "hidden_points.csv", dir / "truth" / "hidden.csv", o.observedSteps);
  const FreeRun c = freeRunOf(dir / "constant" / "hidden_points.csv", dir / "truth" / "hidden.csv",
                              o.observedSteps);
  ASSERT_EQ(w.radius.size(), static_cast<size_t>(o.tumours));
  ASSERT_EQ(w.frames, o.tumours * (o.steps - o.observedSteps));

  for (size_t k = 0; k < w.radius.size(); ++k) {
    ASSERT_EQ(w.radius[k].size(), static_cast<size_t>(o.steps - o.observedSteps + 1));
    int shrinking = 0;
    for (size_t i = 1; i < w.radius[k].size(); ++i)
      if (w.totalRadius[k][i] < w.totalRadius[k][i - 1]) ++shrinking;
    std::cout << "[ phantom ] tumour " << k << ": total radius smaller than the step before on "
              << shrinking << " of " << w.radius[k].size() - 1 << " free steps\n";
    EXPECT_EQ(shrinking, 0) << "tumour " << k;
    std::cout << "[ phantom ] tumour " << k << " radius (parameters) at the last observation "
              << 1e3 * w.radius[k].front() << " mm, end " << 1e3 * w.radius[k].back()
              << " mm; without the walk " << 1e3 * c.radius[k].front() << " -> "
              << 1e3 * c.radius[k].back() << " mm; total " << 1e3 * w.totalRadius[k].front()
              << " -> " << 1e3 * w.totalRadius[k].back() << " mm (without "
              << 1e3 * c.totalRadius[k].front() << " -> " << 1e3 * c.totalRadius[k].back()
              << " mm)\n";
    // The walk leaves the parameters, and so the tumour, more uncertain at the end.
    EXPECT_GT(w.radius[k].back(), c.radius[k].back()) << "tumour " << k;
  }

  // Bounds a factor 1000 either side of the prior, never left by the mean of any step.
  const EstimatedParameter& prior = walking.assimilation->parameters.front();
  ASSERT_EQ(prior.transform.kind(), TransformKind::BoundedLog);
  EXPECT_NEAR(prior.transform.lower(), prior.mean / 1e3, 1e-12 * prior.mean);
  EXPECT_NEAR(prior.transform.upper(), prior.mean * 1e3, 1e-12 * prior.mean);
  EXPECT_NEAR(prior.randomWalkPerStep, o.stiffnessRandomWalk * prior.mean * std::sqrt(o.dt),
              1e-12 * prior.mean);
  const std::vector<double> means = estimatedMeans(dir / "walk" / "estimates.csv");
  ASSERT_EQ(means.size(), static_cast<size_t>((o.steps + 1) * o.groups));
  for (double m : means) {
    EXPECT_GT(m, prior.transform.lower());
    EXPECT_LT(m, prior.transform.upper());
  }

  const double coverage = static_cast<double>(w.inside) / w.frames;
  std::cout << "[ phantom ] free run: tumour error " << 1e3 * w.meanErrorM
            << " mm (without the walk " << 1e3 * c.meanErrorM << "), coverage " << coverage
            << " (without " << static_cast<double>(c.inside) / c.frames << "); validation error "
            << 1e3 * withWalk.estimated.all.meanM << " mm over the run, "
            << 1e3 * withWalk.estimated.freeRun.meanM << " mm free (without "
            << 1e3 * without.estimated.all.meanM << ", " << 1e3 * without.estimated.freeRun.meanM
            << ")\n";
  EXPECT_LE(withWalk.estimated.all.meanM, 1.1 * without.estimated.all.meanM);
  EXPECT_LE(withWalk.estimated.freeRun.meanM, 1.1 * without.estimated.freeRun.meanM);
  EXPECT_LE(w.meanErrorM, 1.1 * c.meanErrorM);
  EXPECT_GE(coverage, 0.9);  // the goal for the free run
}

}  // namespace
}  // namespace bcassim
