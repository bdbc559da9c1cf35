// Rigid pre-alignment (Procrustes, ICP) and barycentric attachment of curves to surfaces.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <string>
#include <vector>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/RigidAlignment.h"
#include "bcassim/atlas/SurfaceAttachment.h"

namespace bcassim {
namespace {

RigidTransform knownMotion() {
  RigidTransform t;
  t.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
  t.translation = Eigen::Vector3d(0.01, -0.02, 0.015);
  return t;
}

TEST(RigidAlignment, ProcrustesRecoversMotionExactly) {
  const Eigen::MatrixX3d P = test::randomMatrix(20, 0.05, 41);
  const RigidTransform t = knownMotion();
  const RigidTransform r = procrustes(P, t.apply(P));
  EXPECT_LT((r.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((r.translation - t.translation).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(r.rotation.determinant(), 1.0, 1e-12);
  EXPECT_THROW(procrustes(P.topRows(2), P.topRows(2)), InputError);
}

TEST(RigidAlignment, IcpAlignsMovedEllipsoid) {
  // An ellipsoid (no rotational symmetry) moved rigidly and retessellated is found again.
  TriMesh target = test::makeIcosphere(1.0, 3);
  target.V = target.V * Eigen::Vector3d(0.08, 0.05, 0.03).asDiagonal();
  TriMesh source = test::makeIcosphere(1.0, 2);
  source.V = source.V * Eigen::Vector3d(0.08, 0.05, 0.03).asDiagonal();
  const RigidTransform t = knownMotion();
  target.V = t.apply(target.V);
  const RigidTransform r = alignRigidly(source, target);
  EXPECT_LT((r.rotation - t.rotation).cwiseAbs().maxCoeff(), 0.02);
  EXPECT_LT((r.translation - t.translation).norm(), 1e-3);
}

TEST(RigidAlignment, MultiStartIcpUndoesAHalfTurn) {
  // A half turn about z on top of a small motion, far beyond the reach of ICP from the identity:
  // one of the 24 axis-aligned starts is within 0.15 rad of it.
  TriMesh target = test::makeIcosphere(1.0, 3);
  target.V = target.V * Eigen::Vector3d(0.08, 0.05, 0.03).asDiagonal();
  // A bump at +x so that the half turn is not a symmetry of the ellipsoid.
  for (Eigen::Index i = 0; i < target.V.rows(); ++i)
    if (target.V(i, 0) > 0.06) target.V(i, 0) += 0.02 * (target.V(i, 0) - 0.06) / 0.02;
  TriMesh source = target;
  RigidTransform t;
  t.rotation =
      Eigen::AngleAxisd(3.14159265358979 + 0.15, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation = Eigen::Vector3d(0.01, -0.02, 0.015);
  target.V = t.apply(target.V);
  double rms = 1.0;
  const RigidTransform r = alignRigidlyMultiStart(source, target, {}, 8, &rms);
  EXPECT_LT((r.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((r.translation - t.translation).norm(), 1e-4);
  EXPECT_LT(rms, 1e-4);  // of a 0.1 m shape (ICP converges slowly near the end)

  // The same motion is an implausible pose for shapes in a scanner's axes: refused beyond 90
  // degrees, and said so with the better fit's rotation and residual.
  MultiStartReport report;
  double limitedRms = 0.0;
  const RigidTransform limited =
      alignRigidlyMultiStart(source, target, {}, 8, &limitedRms, 90.0, &report);
  EXPECT_LE(rotationAngleDegrees(limited.rotation), 90.0 + 1.0);
  EXPECT_DOUBLE_EQ(report.rotationDegrees, rotationAngleDegrees(limited.rotation));
  EXPECT_DOUBLE_EQ(report.rms, limitedRms);
  EXPECT_TRUE(report.rejected);
  EXPECT_NEAR(report.rejectedRotationDegrees, 180.0 - 0.15 * 180.0 / M_PI, 0.1);
  EXPECT_LT(report.rejectedRms, 1e-4);
  EXPECT_GT(limitedRms, 10 * report.rejectedRms);
  // Within the limit nothing is refused.
  alignRigidlyMultiStart(source, target, {}, 8, nullptr, 180.0, &report);
  EXPECT_FALSE(report.rejected);
}

// An ellipsoid made egg-shaped along x (its thick end at -x), (0.08, 0.05, 0.03) m.
TriMesh egg(int level) {
  TriMesh m = test::makeIcosphere(1.0, level);
  m.V = m.V * Eigen::Vector3d(0.08, 0.05, 0.03).asDiagonal();
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const double x = m.V(i, 0);
    m.V(i, 0) = x + 3.0 * x * x;
  }
  return m;
}

TEST(RigidAlignment, SignedAxesTurnWithTheShapeAndTellATurnedPoseApart) {
  const TriMesh e = egg(3);
  const SignedAxes a = signedAxes(e);
  EXPECT_GT(std::abs(a.axes(0, 0)), 0.999);  // the long axis
  EXPECT_GT(a.skewness(0), 0.05);
  TriMesh turned = e;
  const RigidTransform t = knownMotion();
  turned.V = t.apply(e.V);
  const SignedAxes b = signedAxes(turned);
  EXPECT_LT((b.axes.col(0) - t.rotation * a.axes.col(0)).norm(), 1e-9);
  EXPECT_NEAR(b.skewness(0), a.skewness(0), 1e-9);
  const double right = axesAgreement(a, b, t.rotation);
  EXPECT_NEAR(right, a.skewness.sum(), 1e-9);
  // The half turn about z that the ellipsoid could not tell from the motion: the egg can.
  const Eigen::Matrix3d halfTurn =
      t.rotation * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LT(axesAgreement(a, b, halfTurn), right - a.skewness(0));
}

TEST(RigidAlignment, MultiStartSaysWhenTwoPosesFitAlike) {
  // A plain ellipsoid's half turns are symmetries: four poses fit it equally (the source a little
  // larger, so that no fit is exact).
  TriMesh target = test::makeIcosphere(1.0, 3);
  target.V = target.V * Eigen::Vector3d(0.08, 0.05, 0.03).asDiagonal();
  TriMesh source = test::makeIcosphere(1.0, 2);
  source.V = source.V * Eigen::Vector3d(0.082, 0.051, 0.031).asDiagonal();
  MultiStartReport report;
  alignRigidlyMultiStart(source, target, {}, 8, nullptr, 180.0, &report);
  EXPECT_TRUE(report.ambiguous);
  EXPECT_NEAR(report.rivalApartDegrees, 180.0, 1.0);
  EXPECT_LE(report.rivalRms, 1.03 * report.rms);
  const auto doubts = poseDoubts(report, 180.0);
  ASSERT_EQ(doubts.size(), 1u);
  EXPECT_EQ(doubts[0].rfind("two poses 180 deg apart fit alike (RMS ", 0), 0u) << doubts[0];
  // An egg keeps one symmetry, the half turn about its long axis; the pose kept has its thick
  // end where the target's is.
  TriMesh bigger = egg(2);
  bigger.V *= 1.02;
  const RigidTransform kept =
      alignRigidlyMultiStart(bigger, egg(3), {}, 8, nullptr, 180.0, &report);
  EXPECT_TRUE(report.ambiguous);
  EXPECT_NEAR(report.rivalApartDegrees, 180.0, 1.0);
  EXPECT_GT(kept.rotation(0, 0), 0.999);
}

TEST(RigidAlignment, ACurveOnBothSurfacesTellsSymmetricPosesApart) {
  // A plain ellipsoid turned half a turn about z (and a little more): its half turns fit it
  // exactly, so the surface cannot tell the motion from them. A curve drawn on one side of it
  // (edges at x > 0.04 m, z > 0) and moved with it can.
  const TriMesh source = [] {
    TriMesh m = test::makeIcosphere(1.0, 3);
    m.V = m.V * Eigen::Vector3d(0.08, 0.05, 0.03).asDiagonal();
    return m;
  }();
  std::vector<std::array<int, 2>> edges;
  for (Eigen::Index f = 0; f < source.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = source.F(f, k), b = source.F(f, (k + 1) % 3);
      const auto onSide = [&](int v) { return source.V(v, 0) > 0.04 && source.V(v, 2) > 0.0; };
      if (a < b && onSide(a) && onSide(b)) edges.push_back({a, b});
    }
  }
  ASSERT_GE(edges.size(), 10u);
  CurvePair curve;
  curve.source.resize(static_cast<Eigen::Index>(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e)
    curve.source.row(static_cast<Eigen::Index>(e)) << edges[e][0], edges[e][1];
  curve.target = curve.source;  // the target is the moved source: the same vertex ids
  RigidTransform t;
  t.rotation = Eigen::AngleAxisd(M_PI + 0.15, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation = Eigen::Vector3d(0.01, -0.02, 0.015);
  TriMesh target = source;
  target.V = t.apply(source.V);

  MultiStartReport surfaceOnly;
  alignRigidlyMultiStart(source, target, {}, 8, nullptr, 180.0, &surfaceOnly);
  EXPECT_TRUE(surfaceOnly.ambiguous);
  MultiStartReport withCurve;
  double rms = 1.0;
  IcpOptions longer;  // the trimmed curve term slows ICP's last millimetres down
  longer.maxIterations = 300;
  const RigidTransform r =
      alignRigidlyMultiStart(source, target, longer, 8, &rms, 180.0, &withCurve, &curve, 1.0);
  EXPECT_LT((r.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((r.translation - t.translation).norm(), 1e-4);
  EXPECT_LT(rms, 1e-4);
  EXPECT_DOUBLE_EQ(withCurve.rms, rms);
  EXPECT_FALSE(withCurve.ambiguous);  // the symmetric poses put the curve on the wrong side
  // The target's curve labelled shorter (its edges beyond x = 0.045 m only): the source's points
  // past its end, fewer than a fifth, are left out of each step instead of pulling the pose.
  CurvePair shorter = curve;
  std::vector<int> keptEdges;
  for (Eigen::Index e = 0; e < curve.source.rows(); ++e)
    if (source.V(curve.source(e, 0), 0) > 0.045 && source.V(curve.source(e, 1), 0) > 0.045)
      keptEdges.push_back(static_cast<int>(e));
  shorter.target = curve.source(keptEdges, Eigen::placeholders::all);
  ASSERT_LT(shorter.target.rows(), curve.source.rows());
  const RigidTransform rs =
      alignRigidlyMultiStart(source, target, longer, 8, nullptr, 180.0, nullptr, &shorter, 1.0);
  EXPECT_LT((rs.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT((rs.translation - t.translation).norm(), 1e-4);
  // A curve on one surface only: no curve term, the surface's fit.
  const CurvePair half{curve.source, Eigen::MatrixX2i()};
  MultiStartReport oneSided;
  alignRigidlyMultiStart(source, target, {}, 8, nullptr, 180.0, &oneSided, &half, 1.0);
  EXPECT_TRUE(oneSided.ambiguous);
  EXPECT_DOUBLE_EQ(oneSided.rms, surfaceOnly.rms);
  try {
    alignRigidlyMultiStart(source, target, {}, 8, nullptr, 180.0, nullptr, &curve, -1.0);
    FAIL() << "a negative curve weight was taken";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rigid alignment: curve weight must be >= 0, got -1");
  }
  CurvePair outside = curve;
  outside.target(0, 1) = static_cast<int>(target.V.rows());
  try {
    alignRigidlyMultiStart(source, target, {}, 8, nullptr, 180.0, nullptr, &outside, 1.0);
    FAIL() << "a curve edge beyond the surface's vertices was taken";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              fmt::format("rigid alignment: the target curve names vertices {}..{}, its surface "
                          "has 0..{}",
                          outside.target.minCoeff(), target.V.rows(), target.V.rows() - 1));
  }
}

TEST(RigidAlignment, RotationAngleOfAxisAngles) {
  for (double degrees : {0.0, 30.0, 90.0, 165.6, 180.0})
    EXPECT_NEAR(rotationAngleDegrees(
                    Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized())
                        .toRotationMatrix()),
                degrees, 1e-6);
}

TEST(SurfaceAttachment, StoredCoordinatesGiveTheSamePositions) {
  const TriMesh s = test::makeIcosphere(0.05, 2);
  const Eigen::MatrixX3d pts = test::randomMatrix(6, 0.05, 3);
  const SurfaceAttachment a(s, pts);
  const SurfaceAttachment b(a.corners(), a.weights());
  EXPECT_EQ((a.positions(s.V) - b.positions(s.V)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR((a.weights().rowwise().sum().array() - 1.0).abs().maxCoeff(), 0.0, 1e-14);
  EXPECT_THROW(SurfaceAttachment(a.corners(), a.weights().topRows(2)), InputError);
}

TEST(SurfaceAttachment, PointsFollowTheSurface) {
  const TriMesh s = test::makeIcosphere(0.05, 2);
  // A curve of points on the surface: vertex midpoints of some faces.
  Eigen::MatrixX3d curve(10, 3);
  for (int i = 0; i < 10; ++i) {
    const Eigen::Index f = 7 * i;
    curve.row(i) = (s.V.row(s.F(f, 0)) + 2.0 * s.V.row(s.F(f, 1)) + s.V.row(s.F(f, 2))) / 4.0;
  }
  const SurfaceAttachment attached(s, curve);
  EXPECT_LT(attached.projectionDistances().maxCoeff(), 1e-12);
  EXPECT_LT((attached.positions(s.V) - curve).cwiseAbs().maxCoeff(), 1e-12);
  // An affine motion of the vertices moves attached points by the same affine map.
  Eigen::Matrix3d A;
  A << 1.1, 0.2, 0.0, -0.1, 0.9, 0.05, 0.0, 0.1, 1.2;
  const Eigen::RowVector3d b(0.01, 0.0, -0.02);
  const Eigen::MatrixX3d moved = (s.V * A.transpose()).rowwise() + b;
  const Eigen::MatrixX3d expected = (curve * A.transpose()).rowwise() + b;
  EXPECT_LT((attached.positions(moved) - expected).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace bcassim
