// The liver experiment for a new patient (issue 16 point 4): a liver without annotation gets its
// estimation springs from a ligament atlas transferred onto it and its anatomical frame without
// the ridge label; the springs' priors come from a membrane calibrated by `ligament springs`.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/atlas/LigamentAtlas.h"
#include "bcassim/atlas/LigamentAtlasFile.h"
#include "bcassim/experiments/liver/AtlasCurve.h"
#include "bcassim/experiments/liver/LiverPhantom.h"
#include "bcassim/experiments/liver/LiverScenario.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/ligaments/AttachmentCurve.h"
#include "bcassim/mechanics/CubicSpringSet.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/scene/LigamentSpringPriors.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/SmallLiverOptions.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// The phantom's falciform curve (m).
Eigen::MatrixX3d atlasModePhantomCurve(const LiverPhantom& p) {
  return extractAttachmentCurve(p.surface, p.edges, 2, "phantom").points;
}

Eigen::Matrix3d atlasModeRotation(double degrees, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized())
      .toRotationMatrix();
}

// Three "patients" of the phantom's shape, slightly turned and moved, their curves `shift` (m) to
// either side of the phantom's along the lateral axis: an atlas whose mean curve is the phantom's.
LigamentAtlas atlasModeSmallAtlas(const LiverPhantom& p, double shift = 0.004) {
  const Eigen::MatrixX3d curve = atlasModePhantomCurve(p);
  const double shifts[3] = {0.0, -shift, shift};
  const Eigen::Matrix3d turns[3] = {Eigen::Matrix3d::Identity(), atlasModeRotation(4, {0, 0, 1}),
                                    atlasModeRotation(-3, {1, 0, 0})};
  std::vector<AtlasSubject> subjects;
  for (int i = 0; i < 3; ++i) {
    AtlasSubject s{"s" + std::to_string(i), p.surface, curve};
    s.curve.col(0).array() += shifts[i];
    s.surface.V = (p.surface.V * turns[i].transpose()).rowwise() +
                  Eigen::RowVector3d(0.01 * i, -0.005 * i, 0.002);
    s.curve = (s.curve * turns[i].transpose()).rowwise() +
              Eigen::RowVector3d(0.01 * i, -0.005 * i, 0.002);
    subjects.push_back(s);
  }
  LigamentAtlasOptions o;
  o.registration.sigmaV = 0.03;
  o.registration.sigmaW = 0.02;
  o.registration.lbfgs.maxIterations = 5;
  o.planeStepDegrees = 3.0;
  return buildLigamentAtlas(subjects, o);
}

LiverScenarioOptions atlasModeSmallLiver(const fs::path& surface) {
  LiverScenarioOptions o = test::smallLiverOptions();
  o.surface = surface.string();
  o.scale = 1e-3;  // the patient file in mm, as the CT livers
  o.atlasTransferIterations = 20;
  return o;
}

TEST(LiverAtlasMode, UnannotatedLiverGetsItsSpringsOnTheTransferredAtlasCurve) {
  const fs::path dir = test::freshDir();
  const LiverPhantom phantom = makeLiverPhantom();
  writeLigamentAtlas((dir / "atlas").string(), atlasModeSmallAtlas(phantom));

  // The patient: the phantom 5 % larger, turned 10 degrees about the superior axis, in mm, and
  // no .eseg beside it.
  const Eigen::Matrix3d turn = atlasModeRotation(10, {0, 0, 1});
  const double grow = 1.05;
  TriMesh patient = phantom.surface;
  patient.V = 1e3 * grow * patient.V * turn.transpose();
  writeObj((dir / "patient.obj").string(), patient);
  ASSERT_FALSE(fs::exists(dir / "patient.eseg"));

  LiverScenarioOptions o = atlasModeSmallLiver(dir / "patient.obj");
  o.atlas = (dir / "atlas").string();
  const LiverScenario s = prepareLiverScenario(o, (dir / "out").string());
  EXPECT_TRUE(s.atlas.used);
  EXPECT_FALSE(s.annotated);
  EXPECT_EQ(s.atlas.expertDistanceMean, -1.0);  // undefined, never 0
  EXPECT_LT(s.atlas.rotationDegrees, 20.0);

  // The springs' curve lies on the patient's surface...
  const Eigen::MatrixX3d springs = readPoints((dir / "out" / "spring_curve.csv").string());
  ASSERT_GE(springs.rows(), 10);
  TriMesh patientM = patient;
  patientM.V *= 1e-3;
  const SurfaceLocator onPatient(patientM);
  for (Eigen::Index i = 0; i < springs.rows(); ++i)
    EXPECT_LT(onPatient.closest(springs.row(i).transpose()).distance, 1e-6) << "point " << i;
  // ... and where the patient's own (hidden) ligament is: within the atlas' band (its subjects'
  // curves lie 4 mm to either side of it).
  const Eigen::MatrixX3d truth = grow * atlasModePhantomCurve(phantom) * turn.transpose();
  const std::vector<double> d = distancesToPolyline(springs, truth);
  double mean = 0;
  for (double x : d) mean += x / static_cast<double>(d.size());
  EXPECT_GT(s.atlas.meanSigma, 0.001);
  EXPECT_LT(mean, 2 * s.atlas.meanSigma) << "mean distance " << mean << " m";
  std::printf("atlas mode: %d curve points, mean distance %.2f mm, band sigma %.2f mm, %.1f deg\n",
              static_cast<int>(springs.rows()), 1e3 * mean, 1e3 * s.atlas.meanSigma,
              s.atlas.rotationDegrees);

  // The estimation scene uses that curve, the truth (no annotation) the same one.
  const std::string estimate = test::readText(dir / "out" / "estimate.yaml");
  EXPECT_TRUE(test::contains(estimate, "spring_curve.csv"));
  const Eigen::MatrixX3d truthCurve = readPoints((dir / "out" / "curve.csv").string());
  EXPECT_TRUE(truthCurve.isApprox(springs, 1e-9));

  // The frame without the ridge label: the one the annotated phantom gets with its ridge, turned
  // with the patient (the ridge only says which way is up; right-handedness says it too).
  EXPECT_FALSE(s.anatomy.ridgeFound);
  LiverScenarioOptions annotatedOptions = atlasModeSmallLiver(kLiverPhantomName);
  const LiverAnatomy annotated =
      prepareLiverScenario(annotatedOptions, (dir / "annotated").string()).anatomy;
  ASSERT_TRUE(annotated.ridgeFound);
  EXPECT_GT(s.anatomy.lateral.dot(turn * annotated.lateral), 0.95);
  EXPECT_GT(s.anatomy.anterior.dot(turn * annotated.anterior), 0.95);
  EXPECT_GT(s.anatomy.superior.dot(turn * annotated.superior), 0.95);
  std::printf("frame vs the annotated one: cosines %.3f %.3f %.3f\n",
              s.anatomy.lateral.dot(turn * annotated.lateral),
              s.anatomy.anterior.dot(turn * annotated.anterior),
              s.anatomy.superior.dot(turn * annotated.superior));
}

TEST(LiverAtlasMode, TheBandOptionPutsTheEstimationSpringsOnTheBandsEdges) {
  const fs::path dir = test::freshDir();
  const LiverPhantom phantom = makeLiverPhantom();
  // Curves 10 mm to either side: a band wider than the layers' +-4 mm about the mean curve.
  writeLigamentAtlas((dir / "atlas").string(), atlasModeSmallAtlas(phantom, 0.010));
  TriMesh patient = phantom.surface;
  patient.V *= 1e3;
  writeObj((dir / "patient.obj").string(), patient);
  LiverScenarioOptions o = atlasModeSmallLiver(dir / "patient.obj");
  o.atlas = (dir / "atlas").string();
  const LiverScenario plain = prepareLiverScenario(o, (dir / "plain").string());
  o.atlasBand = true;
  const LiverScenario banded = prepareLiverScenario(o, (dir / "band").string());
  EXPECT_TRUE(banded.atlas.band);
  EXPECT_FALSE(plain.atlas.band);

  const Eigen::MatrixX3d curve = readPoints((dir / "band" / "spring_curve.csv").string());
  const Eigen::MatrixX3d lower = readPoints((dir / "band" / "spring_band_lower.csv").string());
  const Eigen::MatrixX3d upper = readPoints((dir / "band" / "spring_band_upper.csv").string());
  ASSERT_EQ(lower.rows(), curve.rows());
  ASSERT_EQ(upper.rows(), curve.rows());
  // The edges lie on the patient, about sigma to either side of the mean curve.
  TriMesh patientM = phantom.surface;
  const SurfaceLocator onPatient(patientM);
  double halfWidth = 0;
  for (Eigen::Index i = 0; i < curve.rows(); ++i) {
    EXPECT_LT(onPatient.closest(lower.row(i).transpose()).distance, 1e-6) << i;
    EXPECT_LT(onPatient.closest(upper.row(i).transpose()).distance, 1e-6) << i;
    halfWidth += 0.5 * (upper.row(i) - lower.row(i)).norm() / static_cast<double>(curve.rows());
  }
  EXPECT_GT(halfWidth, 0.5 * banded.atlas.meanSigma);
  EXPECT_LE(halfWidth, banded.atlas.meanSigma * (1 + 1e-9));

  // The estimation scene names the band, and its springs (as read back) follow its edges: as
  // many as on the mean curve, the first layer on the lower edge, the second on the upper.
  const std::string estimate = test::readText(dir / "band" / "estimate.yaml");
  EXPECT_TRUE(test::contains(estimate,
                             "band: {lower: spring_band_lower.csv, upper: spring_band_upper.csv}"));
  const Scene& scene = *banded.estimateScene;
  const auto& springs = scene.model.springs.springs();
  ASSERT_EQ(springs.size(), plain.estimateScene->model.springs.springs().size());
  // The file says the same (its mesh and springs only: its tracks are the truth run's).
  const YAML::Node file = YAML::LoadFile((dir / "band" / "estimate.yaml").string());
  YAML::Node part;
  part["mesh"] = file["mesh"];
  part["springs"] = file["springs"];
  const Scene fromFile =
      loadSceneFromString(YAML::Dump(part), "springs.yaml", (dir / "band").string());
  ASSERT_EQ(fromFile.model.springs.springs().size(), springs.size());
  for (size_t k = 0; k < springs.size(); ++k) {
    EXPECT_EQ(fromFile.model.springs.springs()[k].tet, springs[k].tet) << k;
    EXPECT_LT((fromFile.model.springs.springs()[k].weights - springs[k].weights).norm(), 1e-9);
  }
  const Eigen::VectorXd x = scene.model.restPositions();
  const size_t perLayer = springs.size() / 2;
  double offEdge = 0, offMean = 0;
  for (size_t k = 0; k < springs.size(); ++k) {
    const Vec3 a = scene.model.springs.attachment(*scene.model.mesh, x, k);
    const Eigen::MatrixX3d at = a.transpose();
    offEdge = std::max(offEdge, distancesToPolyline(at, k < perLayer ? lower : upper)[0]);
    offMean += distancesToPolyline(at, curve)[0] / static_cast<double>(springs.size());
  }
  // Within the coarse mesh's snapping of the edge (its faces cut the phantom's curved surface).
  EXPECT_LT(offEdge, 0.002);
  EXPECT_GT(halfWidth, 0.006);
  EXPECT_GT(offMean, 0.75 * halfWidth);  // the layers about the mean curve lie 4 mm from it
  std::printf(
      "band: half width %.2f mm (sigma %.2f mm), springs <= %.2f mm from their edge, "
      "%.2f mm from the mean curve on average\n",
      1e3 * halfWidth, 1e3 * banded.atlas.meanSigma, 1e3 * offEdge, 1e3 * offMean);
  // The baseline's fixed nodes and the anatomy follow the mean curve in both.
  auto heldLine = [&](const char* run) {
    const std::string text = test::readText(dir / run / "baseline.yaml");
    const size_t at = text.find("the ligament's attachment");
    return at == std::string::npos
               ? std::string("none")
               : text.substr(text.rfind('\n', at) + 1, at - text.rfind('\n', at));
  };
  EXPECT_EQ(heldLine("band"), heldLine("plain"));
  EXPECT_NE(heldLine("band"), "none");
  EXPECT_EQ(banded.fixedNodes, plain.fixedNodes);

  LiverScenarioOptions annotated = atlasModeSmallLiver(kLiverPhantomName);
  annotated.atlasBand = true;
  try {
    prepareLiverScenario(annotated, (dir / "no-atlas").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "liver: --atlas-band spreads the springs over an atlas' band; it needs --atlas "
                 "(or --atlas-livers)");
  }
}

TEST(LiverAtlasMode, UnannotatedLiverWithoutAtlasOrWithAMissingOneIsOneLine) {
  const fs::path dir = test::freshDir();
  TriMesh patient = makeLiverPhantom().surface;
  patient.V *= 1e3;
  writeObj((dir / "patient.obj").string(), patient);
  LiverScenarioOptions o = atlasModeSmallLiver(dir / "patient.obj");
  try {
    prepareLiverScenario(o, (dir / "out").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "patient.eseg").string() +
                  ": missing edge labels (.eseg with label 2 = falciform); a liver without them "
                  "needs an atlas (--atlas)");
  }
  o.atlas = (dir / "no-atlas").string();
  try {
    prepareLiverScenario(o, (dir / "out").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(test::contains(m, (dir / "no-atlas").string())) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// The chain membrane -> springs.yaml -> liver priors, through the command line for the first part.
TEST(LiverNewPatient, SpringPriorsComeFromTheCalibratedMembrane) {
  const fs::path dir = test::freshDir();
  const test::CliResult cal =
      test::runBcassim(dir,
                       "ligament springs --young 403e3 --thickness 1e-3 --width 0.04 --length 0.1 "
                       "--membrane-cells 8 20 1 --out cal");
  ASSERT_EQ(cal.exitCode, 0) << cal.err;
  const std::string yaml = (dir / "cal" / "springs.yaml").string();
  const LigamentSpringPriors perMetre = readLigamentSpringPriors(yaml);
  EXPECT_DOUBLE_EQ(perMetre.restLength, 0.1);

  LiverScenarioOptions o = test::smallLiverOptions();
  const LiverScenario guessed = prepareLiverScenario(o, (dir / "guessed").string());
  o.springPriors = yaml;
  const LiverScenario measured = prepareLiverScenario(o, (dir / "measured").string());

  // Same springs (same curve and mesh), so the priors per spring differ as the priors per metre:
  // the calibrated k_gamma for the liver's 30 mm ligament against 0.4 x 300 N/m per m.
  const LigamentSpringPriors liver = perMetre.forRestLength(o.ligamentLength);
  EXPECT_NEAR(measured.priorStiffness / guessed.priorStiffness,
              liver.kGamma.mean / (o.priorFactor * o.ligamentStiffness), 1e-12);
  // The prior's spread: the calibration's own sigma and 100 % between patients (the default).
  const double rel = perMetre.kGamma.stddev / perMetre.kGamma.mean;
  EXPECT_NEAR(measured.priorStddev / measured.priorStiffness, std::hypot(rel, 1.0), 1e-12);
  o.priorSpread = 0;  // the calibration's sigma alone
  EXPECT_NEAR(
      prepareLiverScenario(o, (dir / "narrow").string()).priorStddev / measured.priorStiffness, rel,
      1e-12);
  const Scene& scene = *measured.estimateScene;
  for (int g = 0; g < 3; ++g) {
    const CubicSpringCoefficients& k = scene.model.springs.coefficients(g);
    EXPECT_DOUBLE_EQ(k.kGamma, measured.priorStiffness);
    EXPECT_NEAR(k.kAlpha / k.kGamma, liver.kAlpha.mean / liver.kGamma.mean,
                1e-12 * k.kAlpha / k.kGamma);
    EXPECT_NEAR(k.kBeta, liver.kBeta.mean / liver.kGamma.mean * k.kGamma,
                1e-12 * k.kGamma + 1e-300);
    const EstimatedParameter& p = scene.assimilation->parameters[static_cast<size_t>(g)];
    EXPECT_DOUBLE_EQ(p.mean, measured.priorStiffness);
    EXPECT_DOUBLE_EQ(p.stddev, measured.priorStddev);
  }
}

}  // namespace
}  // namespace bcassim
