// The ligament-atlas pipeline on synthetic organs with known curves: rigid alignment, template,
// curve statistics, transfer to a patient, comparison of curves and the atlas files.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/AtlasLeaveOneOut.h"
#include "bcassim/atlas/AtlasTransfer.h"
#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/LigamentAtlas.h"
#include "bcassim/atlas/LigamentAtlasFile.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {
namespace {

const Eigen::Vector3d kAxes(0.08, 0.05, 0.04);

// Ellipsoid with bumps towards +x and -z (so that no rotation maps it onto itself; the curves
// below stay off the bumps).
TriMesh organ() {
  TriMesh m = test::makeIcosphere(1.0, 3);
  m.V = m.V * kAxes.asDiagonal();
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    if (m.V(i, 0) > 0.06) m.V(i, 0) += 0.5 * (m.V(i, 0) - 0.06);
    if (m.V(i, 2) < -0.036) m.V(i, 2) += 2.0 * (m.V(i, 2) + 0.036);
  }
  return m;
}

// Curve on the ellipsoid in the plane x = x0: angles t in [-1, 1] rad from +y towards +z.
Eigen::MatrixX3d curveAt(double x0, int n = 201) {
  const double s = std::sqrt(1.0 - x0 * x0 / (kAxes.x() * kAxes.x()));
  Eigen::MatrixX3d c(n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = -1.0 + 2.0 * i / (n - 1);
    c.row(i) << x0, kAxes.y() * s * std::cos(t), kAxes.z() * s * std::sin(t);
  }
  return c;
}

// The atlas template is the first subject centred on its bounding box.
Eigen::RowVector3d organCentre() {
  const TriMesh m = organ();
  return 0.5 * (m.V.colwise().minCoeff() + m.V.colwise().maxCoeff());
}

RigidTransform motion(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& shift) {
  RigidTransform t;
  t.rotation = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  t.translation = shift;
  return t;
}

std::vector<AtlasSubject> subjects(double d) {
  const TriMesh base = organ();
  const RigidTransform moves[3] = {motion(0.0, {0, 0, 1}, {0, 0, 0}),
                                   motion(std::numbers::pi + 0.1, {0, 0, 1}, {0.3, 0.1, -0.2}),
                                   motion(0.2, {1, 1, 0}, {-0.05, 0.02, 0.01})};
  const double xs[3] = {0.0, -d, d};
  std::vector<AtlasSubject> out;
  for (int i = 0; i < 3; ++i) {
    AtlasSubject s;
    s.name = "s";
    s.name +=
        std::to_string(i);  // (gcc 12 warns wrongly about "s" + std::to_string(i): -Wrestrict)
    s.surface = base;
    s.curve = curveAt(xs[i]);
    s.surface.V = moves[i].apply(base.V);
    s.curve = moves[i].apply(s.curve);
    out.push_back(s);
  }
  return out;
}

LigamentAtlasOptions quickOptions() {
  LigamentAtlasOptions o;
  o.registration.sigmaV = 0.03;
  o.registration.sigmaW = 0.015;
  o.registration.lbfgs.maxIterations = 5;
  o.planeStepDegrees = 10.0;
  return o;
}

TEST(LigamentAtlas, MeanAndSigmaOfShiftedCurvesOnMovedOrgans) {
  const double d = 0.015;
  const LigamentAtlas atlas = buildLigamentAtlas(subjects(d), quickOptions());
  ASSERT_EQ(atlas.carriedCurves.size(), 3u);
  for (double rms : atlas.alignmentRms) EXPECT_LT(rms, 5e-4);  // 0.5 mm on a 0.17 m organ
  // The curves span polar angles of about -0.9..0.9 rad around +y: planes inside are crossed by
  // all three (the two planes at the ends, at 50 degrees, by some).
  const CarriedCurve c = carryCurve(atlas.curve, atlas.templ.V);
  int full = 0;
  for (Eigen::Index i = 0; i < c.mean.rows(); ++i) {
    if (atlas.curve.count[i] < 3) continue;
    ++full;
    // Mean of the curves at x = -d, 0, d: the curve at x = 0, shifted like the template by its
    // bounding-box centre, up to the faceting of the level-3 mesh.
    EXPECT_NEAR(c.mean(i, 0), -organCentre().x(), 1e-3) << i;
    const double theta = atlas.curve.planes.planes[atlas.curve.plane[i]].parameter;
    EXPECT_LT(std::abs(theta), 1.0);
    // sigma: RMS of the x offsets (sqrt(2/3) d), plus the small in-plane spread of the two
    // off-centre curves (their cross-sections are smaller).
    EXPECT_NEAR(atlas.curve.sigma(i), std::sqrt(2.0 / 3.0) * d, 0.1 * d) << i;
  }
  EXPECT_GE(full, 9);
}

TEST(LigamentAtlas, ParallelPlanesForCurvesAlongTheTransverseAxis) {
  // Three curves running along x on the organ, at polar angles -0.2, 0, 0.2 rad about x from +y
  // (sections of radius r(x) = b sqrt(1 - x^2/a^2) in y, c sqrt(...) in z). Planes x = const cut
  // each once; the mean of the three crossings lies at polar angle 0.
  std::vector<Eigen::MatrixX3d> curves;
  for (double t : {-0.2, 0.0, 0.2}) {
    Eigen::MatrixX3d c(201, 3);
    for (int i = 0; i < 201; ++i) {
      const double x = -0.05 + 0.1 * i / 200.0, s = std::sqrt(1.0 - x * x / (0.08 * 0.08));
      c.row(i) << x, kAxes.y() * s * std::cos(t), kAxes.z() * s * std::sin(t);
    }
    curves.push_back(c);
  }
  LigamentAtlasOptions o;
  o.planes = CuttingPlaneFamily::Kind::Parallel;
  o.planeSpacing = 0.01;
  const TriMesh templ = organ();
  const CurveAtlas a = ligamentCurveAtlas(templ, curves, o);
  EXPECT_EQ(a.planes.kind, CuttingPlaneFamily::Kind::Parallel);
  EXPECT_NEAR(std::abs(a.planes.axis.x()), 1.0, 1e-15);
  // Planes every 10 mm from the bounding-box centre; those within |x| < 0.05 are crossed.
  ASSERT_GE(a.mean.size(), 9);
  const Eigen::MatrixX3d m = a.mean.positions(templ.V);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    EXPECT_EQ(a.count[i], 3);
    const double x = a.planes.planes[a.plane[i]].point.x();
    EXPECT_NEAR(m(i, 0), x, 1e-3);    // in its plane, up to the projection onto the mesh
    EXPECT_NEAR(m(i, 2), 0.0, 1e-3);  // at polar angle 0
    const double s = std::sqrt(1.0 - x * x / (0.08 * 0.08));
    EXPECT_NEAR(m(i, 1), kAxes.y() * s, 1.5e-3);
    // sigma: RMS distance of the crossings to their mean, sqrt(2/3) times the side offset.
    const Eigen::Vector2d side(kAxes.y() * s * std::cos(0.2), kAxes.z() * s * std::sin(0.2));
    const Eigen::Vector2d centre((kAxes.y() * s + 2.0 * side.x()) / 3.0, 0.0);
    const double sigma = std::sqrt((2.0 * (side - centre).squaredNorm() +
                                    (Eigen::Vector2d(kAxes.y() * s, 0) - centre).squaredNorm()) /
                                   3.0);
    EXPECT_NEAR(a.sigma(i), sigma, 1e-6);
  }
}

TEST(LigamentAtlas, TransferFollowsAScaledRotatedPatient) {
  const LigamentAtlas atlas = buildLigamentAtlas(subjects(0.01), quickOptions());
  // Patient: the organ 10 % larger, turned and moved.
  const RigidTransform m = motion(0.4, {0, 1, 1}, {0.1, 0.2, 0.3});
  TriMesh patient = organ();
  patient.V = m.apply(1.1 * patient.V);
  RegistrationOptions ro = quickOptions().registration;
  ro.lbfgs.maxIterations = 30;
  ro.sigmaW = 0.005;  // sharp enough to fix the tangential slide (0.015: 2.4 mm off)
  const AtlasTransfer t = transferAtlas(atlas, patient, ro);
  EXPECT_LT(t.registration.data, 0.1 * t.registration.initialData);
  // Expected: the atlas mean (at x = 0 of the template) scaled and moved like the patient.
  const CarriedCurve onTemplate = carryCurve(atlas.curve, atlas.templ.V);
  const Eigen::MatrixX3d expected = m.apply(1.1 * (onTemplate.mean.rowwise() + organCentre()));
  const double err = (t.curve.mean - expected).rowwise().norm().maxCoeff();
  const double meanErr = (t.curve.mean - expected).rowwise().norm().mean();
  // Rigid alignment alone leaves the 10 % size difference: the curve off by about 5 mm.
  const double rigidErr = (carryCurve(atlas.curve, t.rigid.apply(atlas.templ.V)).mean - expected)
                              .rowwise()
                              .norm()
                              .mean();
  std::printf("transfer error: mean %.2f mm, max %.2f mm (rigid only: mean %.2f mm)\n",
              1e3 * meanErr, 1e3 * err, 1e3 * rigidErr);
  EXPECT_LT(err, 0.5e-3) << "max error " << err << " m";
  EXPECT_GT(rigidErr, 4e-3);
  // The band is carried too, with about the atlas sigma scaled by 1.1.
  for (Eigen::Index i = 0; i < t.curve.sigma.rows(); ++i)
    EXPECT_NEAR(t.curve.sigma(i), 1.1 * onTemplate.sigma(i),
                0.3 * onTemplate.sigma(i));  // Projected onto the patient: on its surface, and no
                                             // farther from the expected curve.
  const AtlasTransfer p = transferAtlas(atlas, patient, ro, true, true);
  const SurfaceLocator onPatient(patient);
  for (Eigen::Index i = 0; i < p.curve.mean.rows(); ++i) {
    EXPECT_LT(onPatient.closest(p.curve.mean.row(i).transpose()).distance, 1e-12) << i;
    EXPECT_LT((p.curve.mean.row(i) - expected.row(i)).norm(), 0.5e-3) << i;
  }
}

TEST(LigamentAtlas, FilesRoundTrip) {
  const LigamentAtlas atlas = buildLigamentAtlas(subjects(0.01), quickOptions());
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "bcassim-test-atlas-files";
  writeLigamentAtlas(dir.string(), atlas);
  const LigamentAtlas back = readLigamentAtlas(dir.string());
  EXPECT_EQ(back.templ.F, atlas.templ.F);
  EXPECT_EQ((back.templ.V - atlas.templ.V).cwiseAbs().maxCoeff(), 0.0);
  const CarriedCurve a = carryCurve(atlas.curve, atlas.templ.V);
  const CarriedCurve b = carryCurve(back.curve, back.templ.V);
  EXPECT_EQ((a.mean - b.mean).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((a.upper - b.upper).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(back.curve.plane, atlas.curve.plane);
  EXPECT_EQ(back.curve.planes.planes.size(), atlas.curve.planes.planes.size());
  EXPECT_EQ(back.carriedCurves.size(), 3u);
  EXPECT_EQ(back.templRidge.rows(), 0);  // the subjects label no ridge: no file, none read
  EXPECT_FALSE(std::filesystem::exists(dir / "template_ridge.csv"));
  EXPECT_THROW(readLigamentAtlas((dir / "nothing").string()), InputError);

  // The template's ridge travels with the atlas; a bad vertex index is one line.
  std::vector<AtlasSubject> ridged = subjects(0.01);
  ridged[0].ridge.resize(2, 2);
  ridged[0].ridge << 0, 1, 1, 2;
  const LigamentAtlas withRidge = buildLigamentAtlas(ridged, quickOptions());
  EXPECT_EQ(withRidge.templRidge, ridged[0].ridge);
  writeLigamentAtlas(dir.string(), withRidge);
  EXPECT_EQ(readLigamentAtlas(dir.string()).templRidge, ridged[0].ridge);
  std::ofstream(dir / "template_ridge.csv") << "v0,v1\n0,1\n1,99999\n";
  try {
    readLigamentAtlas(dir.string());
    FAIL() << "a vertex index out of range was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "template_ridge.csv").string() +
                                         ":3: expected a vertex index of the template, 0.." +
                                         std::to_string(withRidge.templ.V.rows() - 1) +
                                         ", got 99999");
  }
  std::filesystem::remove_all(dir);
}

TEST(CurveComparison, ParallelCurvesAtKnownDistance) {
  // Two arcs at x = 0 and x = 0.004: every radial plane around x sees them 4 mm apart, and every
  // point of one is 4 mm from the other.
  const Eigen::MatrixX3d a = curveAt(0.0, 401), b = curveAt(0.004, 401);
  const CuttingPlaneFamily f =
      radialPlanes({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, evenAngles(-0.75, 0.75, 7));
  const CurveDistance d = compareCurves(a, b, f);
  EXPECT_EQ(d.planes, 7);
  // The cross-section at x = 0.004 is smaller by a factor sqrt(1 - (0.004/0.08)^2).
  const double shrink = 0.05 * (1.0 - std::sqrt(1.0 - 0.0025));
  EXPECT_GT(d.planeMean, 0.004);
  EXPECT_LT(d.planeMax, std::hypot(0.004, shrink) + 1e-9);
  EXPECT_NEAR(d.pointMean, 0.004, shrink + 1e-6);
  // A point beyond the end of a segment is measured to the end point.
  Eigen::MatrixX3d seg(2, 3);
  seg << 0, 0, 0, 1, 0, 0;
  EXPECT_DOUBLE_EQ(distanceToPolyline({2, 1, 0}, seg), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(distanceToPolyline({0.5, 0, 3}, seg), 3.0);
}

}  // namespace
}  // namespace bcassim

namespace bcassim {
namespace {

// The organs of subjects(d) plus a fourth copy of the first (curve at x = 0), scaled by `scale`
// and rigidly moved unless `moved` is false.
std::vector<AtlasSubject> fourOrgans(double d, double scale = 1.0, bool moved = true) {
  std::vector<AtlasSubject> s = subjects(d);
  AtlasSubject fourth = s[0];
  fourth.name = "s3";
  const RigidTransform m = motion(moved ? 0.3 : 0.0, {0, 1, 0}, {moved ? 0.02 : 0.0, 0.0, 0.0});
  fourth.surface.V = m.apply(scale * fourth.surface.V);
  fourth.curve = m.apply(scale * fourth.curve);
  s.push_back(fourth);
  return s;
}

// Folds holding out the fourth and the second organ; planes crossed by all remaining curves.
LeaveOneOutOptions foldsOfFourOrgans() {
  LeaveOneOutOptions o;
  o.atlas = quickOptions();
  o.atlas.minCrossingFraction = 0.9;
  o.heldOut = {3, 1};
  return o;
}

TEST(AtlasLeaveOneOut, HeldOutErrorIsTheOffsetFromTheOthersMean) {
  // Four copies of the organ, rigidly moved, with curves at x = 0 (template), -d, +d and 0.
  // Holding out the fourth leaves curves at 0, -d, d: mean at 0, error ~ 0. Holding out the
  // second (at -d) leaves 0, d, 0: mean at d/3, error 4d/3.
  const double d = 0.009;
  const std::vector<AtlasSubject> s = fourOrgans(d);
  const LeaveOneOutOptions o = foldsOfFourOrgans();
  const LeaveOneOutResult r = leaveOneOut(s, o);
  ASSERT_EQ(r.folds.size(), 2u);
  EXPECT_GE(r.folds[0].distance.planes, 5);
  EXPECT_LT(r.folds[0].distance.planeMean, 1e-3);
  EXPECT_NEAR(r.folds[1].distance.planeMean, 4.0 * d / 3.0, 1.5e-3);
  EXPECT_THROW(leaveOneOut({s[0], s[1]}, o), InputError);
}

TEST(AtlasLeaveOneOut, FrechetTemplateGivesTheSameOffsets) {
  // The organs of the first test are the same shape: their Fréchet mean is that shape, and the
  // errors are those of the fixed template (about 0 and 4d/3).
  const double d = 0.009;
  const std::vector<AtlasSubject> s = fourOrgans(d, 1.0, false);
  LeaveOneOutOptions o = foldsOfFourOrgans();
  o.frechetTemplate = true;
  o.templateIterations = 3;
  const LeaveOneOutResult r = leaveOneOut(s, o);
  ASSERT_EQ(r.folds.size(), 2u);
  EXPECT_GT(r.dataRatio[0], 0.0);  // the template subject is registered too
  EXPECT_GE(r.folds[0].distance.planes, 5);
  EXPECT_LT(r.folds[0].distance.planeMean, 1e-3);
  EXPECT_NEAR(r.folds[1].distance.planeMean, 4.0 * d / 3.0, 1.5e-3);
}

TEST(AtlasLeaveOneOut, ScaleAlignmentMeasuresInTheSubjectsOwnSize) {
  // As above, the fourth organ (curve at x = 0) 30 % larger: with size normalisation it is scaled
  // to the template's area (factor 1 / 1.3) and its error is still about zero; the second organ
  // (curve at -d, same size as the template) still gets 4d/3.
  const double d = 0.009;
  const std::vector<AtlasSubject> s = fourOrgans(d, 1.3);
  EXPECT_NEAR(areaMatchingScale(s[3].surface, s[0].surface), 1.0 / 1.3, 1e-12);
  LeaveOneOutOptions o = foldsOfFourOrgans();
  o.scaleAlign = true;
  o.projectOntoSubject = true;
  const LeaveOneOutResult r = leaveOneOut(s, o);
  ASSERT_EQ(r.folds.size(), 2u);
  EXPECT_NEAR(r.scale[3], 1.0 / 1.3, 1e-12);
  EXPECT_NEAR(r.scale[1], 1.0, 1e-12);
  EXPECT_GE(r.folds[0].distance.planes, 5);
  EXPECT_LT(r.folds[0].distance.planeMean, 1e-3);
  EXPECT_NEAR(r.folds[1].distance.planeMean, 4.0 * d / 3.0, 1.5e-3);
}

TEST(AtlasLeaveOneOut, NearestShapesLeaveTheOddOneOut) {
  // The fourth organ (curve at x = 0) 30 % larger, not size-normalised: its registered template is
  // the farthest in shape from the others. Holding out the second (curve at -d), its 2 nearest
  // shapes are the template and the third (curves at 0 and +d): mean d/2, error 3d/2, where all
  // three give d/3 and 4d/3. Every training liver (3, or more asked) is the plain fold.
  const double d = 0.009;
  const std::vector<AtlasSubject> s = fourOrgans(d, 1.3);
  LeaveOneOutOptions o = foldsOfFourOrgans();
  o.heldOut = {1};
  o.nearestCounts = {2, 3, 5};
  const LeaveOneOutResult r = leaveOneOut(s, o);
  ASSERT_EQ(r.folds.size(), 1u);
  const LeaveOneOutFold& f = r.folds[0];
  ASSERT_EQ(f.nearest.size(), 3u);
  ASSERT_EQ(f.nearestBand.size(), 3u);
  EXPECT_NEAR(f.distance.planeMean, 4.0 * d / 3.0, 1.5e-3);
  EXPECT_NEAR(f.nearest[0].planeMean, 3.0 * d / 2.0, 1.5e-3);
  EXPECT_GT(f.nearest[0].planeMean, f.distance.planeMean + 0.5 * (3.0 / 2.0 - 4.0 / 3.0) * d);
  for (int k : {1, 2}) {
    EXPECT_EQ(f.nearest[static_cast<size_t>(k)].planes, f.distance.planes);
    EXPECT_NEAR(f.nearest[static_cast<size_t>(k)].planeMean, f.distance.planeMean, 1e-12);
  }
  std::printf("all three: %.4g mm, the 2 nearest: %.4g mm\n", 1e3 * f.distance.planeMean,
              1e3 * f.nearest[0].planeMean);
}

TEST(AtlasLeaveOneOut, FusedTemplatesThatAgreeGiveTheirCurve) {
  // The organs are one shape, so every template transfers the same training curves: their fused
  // curve is each one's (about 0 for the fourth, 4d/3 for the second), whatever the frames in
  // between — the fourth organ is 30 % larger and moved, the second fusion template is it, and the
  // curves go through each liver's own frame. The fourth is never held out by its own run: its
  // fold fuses two curves, the second's three.
  const double d = 0.009;
  const std::vector<AtlasSubject> s = fourOrgans(d, 1.3);
  LeaveOneOutOptions o = foldsOfFourOrgans();
  o.scaleAlign = true;
  o.projectOntoSubject = true;
  o.fusionTemplates = {2, 3};
  const LeaveOneOutResult r = leaveOneOut(s, o);
  ASSERT_EQ(r.folds.size(), 2u);
  const LeaveOneOutFold &fourth = r.folds[0], &second = r.folds[1];
  EXPECT_EQ(fourth.fusedCurves, 2);
  EXPECT_EQ(second.fusedCurves, 3);
  EXPECT_GE(fourth.fused.planes, 5);
  EXPECT_LT(fourth.fused.planeMean, 1e-3);
  EXPECT_NEAR(second.fused.planeMean, 4.0 * d / 3.0, 1.5e-3);
  EXPECT_NEAR(second.fused.planeMean, second.distance.planeMean, 1e-3);
  // The transferred curve in the fourth organ's own frame lies on its curve.
  double far = 0;
  for (Eigen::Index i = 0; i < fourth.predicted.rows(); ++i)
    far = std::max(far, distanceToPolyline(fourth.predicted.row(i).transpose(), s[3].curve));
  EXPECT_LT(far, 2e-3);
  o.fusionTemplates = {0};
  EXPECT_THROW(
      {
        try {
          leaveOneOut(s, o);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "leave-one-out: cannot fuse template subject 0");
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace bcassim
