// Varifold and current distances (eq. 4.5): equal to a naive double sum, zero on identical meshes,
// invariant to vertex and face order (and, for the varifold, to orientation), exact gradients.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numeric>
#include <random>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/Error.h"
#include "bcassim/atlas/CurrentDistance.h"
#include "bcassim/atlas/VarifoldDistance.h"

namespace bcassim {
namespace {

constexpr double kSigmaW = 0.02;

// Direct transcription of eq. 4.5 with std::exp, one pair at a time.
double naiveInner(const TriMesh& s, const TriMesh& t, bool varifold) {
  auto face = [](const TriMesh& m, Eigen::Index f, Eigen::Vector3d* c, Eigen::Vector3d* n) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), d = m.V.row(m.F(f, 2));
    *c = (a + b + d) / 3.0;
    *n = 0.5 * (b - a).cross(d - a);
  };
  long double sum = 0.0;
  for (Eigen::Index i = 0; i < s.F.rows(); ++i) {
    for (Eigen::Index j = 0; j < t.F.rows(); ++j) {
      Eigen::Vector3d ci, ni, dj, mj;
      face(s, i, &ci, &ni);
      face(t, j, &dj, &mj);
      const double k = std::exp(-(ci - dj).squaredNorm() / (kSigmaW * kSigmaW));
      const double dot = ni.dot(mj);
      sum += varifold ? k * dot * dot / (ni.norm() * mj.norm()) : k * dot;
    }
  }
  return static_cast<double>(sum);
}

double naiveDistance(const TriMesh& s, const TriMesh& t, bool varifold) {
  return naiveInner(s, s, varifold) + naiveInner(t, t, varifold) - 2.0 * naiveInner(s, t, varifold);
}

TriMesh source() {
  TriMesh m = test::makeIcosphere(0.05, 2);
  m.V += test::randomMatrix(m.V.rows(), 0.002, 11);
  return m;
}
TriMesh target() { return test::makeIcosphere(0.045, 3, {0.01, -0.005, 0.0}); }

TEST(SurfaceDistances, EqualNaiveDoubleSum) {
  const TriMesh s = source(), t = target();
  for (bool varifold : {true, false}) {
    const double expected = naiveDistance(s, t, varifold);
    const double got = varifold ? VarifoldDistance(t, kSigmaW).value(s.V, s.F)
                                : CurrentDistance(t, kSigmaW).value(s.V, s.F);
    EXPECT_GT(expected, 0.0);
    EXPECT_NEAR(got, expected, 1e-10 * expected) << (varifold ? "varifold" : "current");
    // The inner products themselves, where the distance's cancellation cannot hide errors.
    const FaceKernelKind kind = varifold ? FaceKernelKind::Varifold : FaceKernelKind::Current;
    const double st =
        faceKernelSum(orientedFaces(s.V, s.F), orientedFaces(t.V, t.F), kSigmaW, kind);
    const double naiveSt = naiveInner(s, t, varifold);
    EXPECT_NEAR(st, naiveSt, 1e-12 * std::abs(naiveSt));
  }
}

// Meshes of many blocks and tiles, one far part skipped by the cutoff, one partly overlapping.
TEST(SurfaceDistances, InnerProductsEqualNaiveSumOnLargerMeshes) {
  const TriMesh s = test::makeIcosphere(0.05, 3);
  const TriMesh t = test::makeIcosphere(0.04, 3, {0.06, 0.02, 0.0});
  for (bool varifold : {true, false}) {
    const FaceKernelKind kind = varifold ? FaceKernelKind::Varifold : FaceKernelKind::Current;
    const OrientedFaces os = orientedFaces(s.V, s.F), ot = orientedFaces(t.V, t.F);
    const double naiveSt = naiveInner(s, t, varifold), naiveSs = naiveInner(s, s, varifold);
    EXPECT_NEAR(faceKernelSum(os, ot, kSigmaW, kind), naiveSt, 1e-12 * std::abs(naiveSt));
    EXPECT_NEAR(faceKernelSum(os, os, kSigmaW, kind), naiveSs, 1e-12 * std::abs(naiveSs));
    // Deterministic: the same sum twice, bit for bit, whatever the thread schedule.
    EXPECT_EQ(faceKernelSum(os, ot, kSigmaW, kind), faceKernelSum(os, ot, kSigmaW, kind));
  }
}

TEST(SurfaceDistances, ZeroForIdenticalMeshes) {
  const TriMesh t = target();
  const VarifoldDistance v(t, kSigmaW);
  const CurrentDistance c(t, kSigmaW);
  EXPECT_NEAR(v.value(t.V, t.F), 0.0, 1e-13 * v.targetSquaredNorm());
  EXPECT_NEAR(c.value(t.V, t.F), 0.0, 1e-13 * c.targetSquaredNorm());
  Eigen::MatrixX3d g;
  v.valueAndGradient(t.V, t.F, &g);
  EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-12 * v.targetSquaredNorm() / kSigmaW);
}

TEST(SurfaceDistances, InvariantToVertexAndFaceOrder) {
  const TriMesh s = source(), t = target();
  std::vector<int> perm(s.V.rows());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(3));
  TriMesh p;
  p.V.resize(s.V.rows(), 3);
  p.F.resize(s.F.rows(), 3);
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) p.V.row(perm[i]) = s.V.row(i);
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    // Faces reversed in order and rotated cyclically (same orientation).
    const Eigen::Index g = s.F.rows() - 1 - f;
    p.F.row(g) << perm[s.F(f, 1)], perm[s.F(f, 2)], perm[s.F(f, 0)];
  }
  const VarifoldDistance v(t, kSigmaW);
  const CurrentDistance c(t, kSigmaW);
  EXPECT_NEAR(v.value(p.V, p.F), v.value(s.V, s.F), 1e-12 * v.value(s.V, s.F));
  EXPECT_NEAR(c.value(p.V, p.F), c.value(s.V, s.F), 1e-12 * c.value(s.V, s.F));
}

TEST(SurfaceDistances, VarifoldBlindToOrientationCurrentIsNot) {
  const TriMesh s = source(), t = target();
  TriMesh flipped = s;
  flipped.F.col(1).swap(flipped.F.col(2));
  const VarifoldDistance v(t, kSigmaW);
  const CurrentDistance c(t, kSigmaW);
  EXPECT_NEAR(v.value(flipped.V, flipped.F), v.value(s.V, s.F), 1e-12 * v.value(s.V, s.F));
  // Reversed, the source's current is the negative: |-S - T|^2 = |S + T|^2, much larger.
  EXPECT_GT(c.value(flipped.V, flipped.F), 10.0 * c.value(s.V, s.F));
}

void checkGradient(const SurfaceDistance& d, const TriMesh& s) {
  Eigen::MatrixX3d g;
  const double value = d.valueAndGradient(s.V, s.F, &g);
  EXPECT_NEAR(value, d.value(s.V, s.F), 1e-14 * value);
  const double h = 1e-7;
  double maxErr = 0.0;
  for (Eigen::Index i = 0; i < s.V.rows(); i += 3) {
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixX3d p = s.V, m = s.V;
      p(i, c) += h;
      m(i, c) -= h;
      const double fd = (d.value(p, s.F) - d.value(m, s.F)) / (2 * h);
      maxErr = std::max(maxErr, std::abs(fd - g(i, c)));
    }
  }
  EXPECT_LT(maxErr, 1e-6 * g.cwiseAbs().maxCoeff());
}

TEST(SurfaceDistances, VarifoldGradientMatchesFiniteDifferences) {
  checkGradient(VarifoldDistance(target(), kSigmaW), source());
}

TEST(SurfaceDistances, CurrentGradientMatchesFiniteDifferences) {
  checkGradient(CurrentDistance(target(), kSigmaW), source());
}

TEST(SurfaceDistances, RejectBadInput) {
  const TriMesh t = target();
  EXPECT_THROW(VarifoldDistance(t, -1.0), InputError);
  TriMesh bad = t;
  bad.F(0, 0) = static_cast<int>(t.V.rows());
  EXPECT_THROW(VarifoldDistance(t, kSigmaW).value(bad.V, bad.F), InputError);
}

}  // namespace
}  // namespace bcassim
