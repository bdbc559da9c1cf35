// The multi-object data term (a curve on the surface matched with it), its registration, and the
// comparison of a predicted curve with a whole annotated band.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <vector>

#include "AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/CurveKernelDistance.h"
#include "bcassim/atlas/MultiObjectDistance.h"
#include "bcassim/atlas/Registration.h"

namespace {
using namespace bcassim;

constexpr double kRadius = 0.05;
constexpr double kSigmaW = 0.01;

// The sphere's edges whose two ends lie within `halfWidth` of the half-plane y = 0, x > 0: a
// meridian band drawn on the surface (a set of edges, not a path, as .eseg labels are).
Eigen::MatrixX2i meridianEdges(const TriMesh& m, double halfWidth) {
  std::vector<std::array<int, 2>> e;
  auto on = [&](int v) { return std::abs(m.V(v, 1)) < halfWidth && m.V(v, 0) > 0.0; };
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      if (a < b && on(a) && on(b)) e.push_back({a, b});
    }
  Eigen::MatrixX2i out(static_cast<Eigen::Index>(e.size()), 2);
  for (size_t i = 0; i < e.size(); ++i) out.row(static_cast<Eigen::Index>(i)) << e[i][0], e[i][1];
  return out;
}

Eigen::MatrixX3d rotatedAboutZ(const Eigen::MatrixX3d& V, double degrees) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return V * R.transpose();
}

TEST(CurveKernelDistance, ZeroOnItselfBlindToEdgeDirectionAndGradientMatchesFiniteDifferences) {
  const TriMesh s = test::makeIcosphere(kRadius, 3);
  const Eigen::MatrixX2i e = meridianEdges(s, 0.012);
  ASSERT_GE(e.rows(), 10);
  const CurveKernelDistance self(s.V, e, e, kSigmaW);
  EXPECT_NEAR(self.value(s.V), 0.0, 1e-13 * self.targetSquaredNorm());
  Eigen::MatrixX2i reversed = e.rowwise().reverse();
  EXPECT_NEAR(CurveKernelDistance(s.V, reversed, e, kSigmaW).value(s.V), 0.0,
              1e-13 * self.targetSquaredNorm());

  const Eigen::MatrixX3d moved = rotatedAboutZ(s.V, 12.0) + test::randomMatrix(s.V.rows(), 1e-3, 7);
  const CurveKernelDistance d(rotatedAboutZ(s.V, 25.0), e, e, kSigmaW);
  Eigen::MatrixX3d g = Eigen::MatrixX3d::Zero(s.V.rows(), 3);
  const double value = d.addValueAndGradient(moved, &g);
  EXPECT_NEAR(value, d.value(moved), 1e-14 * value);
  EXPECT_GT(value, 0.01 * d.targetSquaredNorm());
  const double h = 1e-7;
  double maxErr = 0.0;
  for (Eigen::Index row = 0; row < e.rows(); ++row)
    for (int c = 0; c < 3; ++c) {
      const int v = e(row, 0);
      Eigen::MatrixX3d p = moved, m = moved;
      p(v, c) += h;
      m(v, c) -= h;
      maxErr = std::max(maxErr, std::abs((d.value(p) - d.value(m)) / (2 * h) - g(v, c)));
    }
  EXPECT_LT(maxErr, 1e-6 * g.cwiseAbs().maxCoeff());
  // Vertices off the curve do not enter it.
  std::vector<bool> onCurve(static_cast<size_t>(s.V.rows()), false);
  for (Eigen::Index row = 0; row < e.rows(); ++row) onCurve[e(row, 0)] = onCurve[e(row, 1)] = true;
  for (Eigen::Index v = 0; v < s.V.rows(); ++v)
    if (!onCurve[v]) {
      EXPECT_EQ(g.row(v).norm(), 0.0) << "vertex " << v;
    }
}

TEST(MultiObjectDistance, WeighsEachObjectByItsOwnSizeAndItsGradientMatchesFiniteDifferences) {
  const TriMesh t = test::makeIcosphere(kRadius, 2);
  const Eigen::MatrixX2i e = meridianEdges(t, 0.015);
  TriMesh s = t;
  s.V = rotatedAboutZ(t.V, 10.0) * 1.05;
  const MultiObjectDistance d(t, e, e, kSigmaW, FaceKernelKind::Varifold, 0.5);
  const FaceKernelDistance surface(t, kSigmaW, FaceKernelKind::Varifold);
  const CurveKernelDistance curve(t.V, e, e, kSigmaW);
  const double w = 0.5 * surface.targetSquaredNorm() / curve.targetSquaredNorm();
  EXPECT_NEAR(d.curveWeight(), w, 1e-14 * w);
  EXPECT_NEAR(d.value(s.V, s.F), surface.value(s.V, s.F) + w * curve.value(s.V),
              1e-12 * d.value(s.V, s.F));
  Eigen::MatrixX3d g;
  const double value = d.valueAndGradient(s.V, s.F, &g);
  EXPECT_NEAR(value, d.value(s.V, s.F), 1e-13 * value);
  const double h = 1e-7;
  double maxErr = 0.0;
  for (Eigen::Index row = 0; row < e.rows(); row += 2)
    for (int c = 0; c < 3; ++c) {
      const int v = e(row, 1);
      Eigen::MatrixX3d p = s.V, m = s.V;
      p(v, c) += h;
      m(v, c) -= h;
      maxErr = std::max(maxErr, std::abs((d.value(p, s.F) - d.value(m, s.F)) / (2 * h) - g(v, c)));
    }
  EXPECT_LT(maxErr, 1e-6 * g.cwiseAbs().maxCoeff());

  RegistrationOptions o;
  o.sigmaW = kSigmaW;
  const CurvePair pair{e, e};
  EXPECT_NE(dynamic_cast<MultiObjectDistance*>(makeDataTerm(t, o, &pair).get()), nullptr);
  EXPECT_NE(dynamic_cast<FaceKernelDistance*>(makeDataTerm(t, o, nullptr).get()), nullptr);
  const CurvePair none{e, Eigen::MatrixX2i()};
  EXPECT_NE(dynamic_cast<FaceKernelDistance*>(makeDataTerm(t, o, &none).get()), nullptr);
  o.curveWeight = -1.0;
  try {
    makeDataTerm(t, o, &pair);
    FAIL() << "a negative weight was accepted";
  } catch (const InputError& err) {
    EXPECT_STREQ(err.what(), "curve data-term weight must be >= 0, got -1");
  }
}

// A sphere turned about its axis is the same surface: the surfaces alone cannot tell the turn,
// the curve drawn on both can. The curve's points must follow the turn with the multi-object
// term and stay put without it.
TEST(MultiObjectDistance, RegistrationRecoversATurnThatTheSurfaceAloneCannotSee) {
  const TriMesh source = test::makeIcosphere(kRadius, 3);
  const Eigen::MatrixX2i e = meridianEdges(source, 0.012);
  TriMesh target = source;
  target.V = rotatedAboutZ(source.V, 20.0);
  // Where each curve vertex of the source should go.
  auto curveError = [&](const Eigen::MatrixX3d& deformed) {
    double sum = 0.0;
    for (Eigen::Index r = 0; r < e.rows(); ++r)
      for (int k = 0; k < 2; ++k) sum += (deformed.row(e(r, k)) - target.V.row(e(r, k))).norm();
    return sum / (2.0 * static_cast<double>(e.rows()));
  };
  RegistrationOptions o;
  o.sigmaV = 0.03;
  o.sigmaW = kSigmaW;
  o.lbfgs.maxIterations = 60;
  const double before = curveError(source.V);
  EXPECT_GT(before, 0.005);
  const RegistrationResult alone = registerSurface(source, target, o);
  const CurvePair pair{e, e};
  const RegistrationResult both = registerSurface(source, target, o, &pair);
  const double errAlone = curveError(alone.deformedVertices);
  const double errBoth = curveError(both.deformedVertices);
  // Measured: 11.7 mm before, 11.7 mm with the surfaces alone, 0.3 mm with the curve.
  EXPECT_GT(errAlone, 0.9 * before);
  EXPECT_LT(errBoth, 0.1 * before) << "alone " << errAlone << " m, before " << before << " m";
  // The surface still matches.
  const FaceKernelDistance surface(target, kSigmaW, FaceKernelKind::Varifold);
  EXPECT_LT(surface.value(both.deformedVertices, source.F), 0.05 * surface.targetSquaredNorm());
}

TEST(CurveComparison, ABandCountsAPredictionInsideItAsZeroAndOutsideByItsNearestEdge) {
  // A strip of triangles along x, as a labelled band is: two rails 4 mm apart (y = 0 and
  // y = 4 mm), rungs, and diagonals, which the planes x = 10 k + 5 mm cross at y = 2 mm.
  const int n = 11;
  Eigen::MatrixX3d V(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    V.row(i) << 0.01 * i, 0.0, 0.0;
    V.row(n + i) << 0.01 * i, 0.004, 0.0;
  }
  Eigen::MatrixX2i band(4 * n - 3, 2);
  int r = 0;
  for (int i = 0; i + 1 < n; ++i) {
    band.row(r++) << i, i + 1;
    band.row(r++) << n + i, n + i + 1;
    band.row(r++) << i, n + i + 1;
  }
  for (int i = 0; i < n; ++i) band.row(r++) << i, n + i;
  std::vector<double> offsets;
  for (int k = 0; k < 9; ++k) offsets.push_back(0.01 * k + 0.005);
  const CuttingPlaneFamily planes = parallelPlanes({0, 0, 0}, {1, 0, 0}, offsets);
  Eigen::MatrixX3d inside(2, 3), outside(2, 3);
  inside << -0.01, 0.002, 0.0, 0.12, 0.002, 0.0;
  outside << -0.01, 0.007, 0.0, 0.12, 0.007, 0.0;
  const CurveDistance in = compareCurveToBand(V, band, inside, planes);
  EXPECT_EQ(in.planes, 9);
  EXPECT_NEAR(in.planeMean, 0.0, 1e-15);  // inside the band
  EXPECT_NEAR(in.pointMax, 0.002, 1e-15);
  const CurveDistance out = compareCurveToBand(V, band, outside, planes);
  EXPECT_EQ(out.planes, 9);
  EXPECT_NEAR(out.planeMean, 0.003, 1e-15);
  EXPECT_NEAR(out.planeMax, 0.003, 1e-15);
  // The path along one rail: the prediction between the rails is 2 mm off it.
  EXPECT_NEAR(compareCurves(V.topRows(n), inside, planes).planeMean, 0.002, 1e-15);
  Eigen::MatrixX2i bad = band;
  bad(0, 1) = 2 * n;
  try {
    compareCurveToBand(V, bad, inside, planes);
    FAIL() << "an index out of range was accepted";
  } catch (const InputError& err) {
    EXPECT_STREQ(err.what(), "curve distance: band vertex index out of range [0, 22)");
  }
}

}  // namespace
