// Each sigma-point set reproduces a given mean and covariance exactly, for random SPD covariances.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/CanonicalSigmaPoints.h"
#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/assimilation/SimplexSigmaPoints.h"
#include "bcassim/assimilation/StarSigmaPoints.h"

namespace bcassim {
namespace {

std::vector<std::pair<const char*, SigmaPointSet>> setsOfDimension(Eigen::Index n) {
  return {{"star", starSigmaPoints(n)},
          {"star kappa 2", starSigmaPoints(n, 2.0)},
          {"canonical", canonicalSigmaPoints(n)},
          {"simplex", simplexSigmaPoints(n)}};
}

TEST(SigmaPoints, CountsAndUnitMoments) {
  for (Eigen::Index n : {1, 2, 5, 12}) {
    EXPECT_EQ(starSigmaPoints(n).count(), 2 * n + 1);
    EXPECT_EQ(canonicalSigmaPoints(n).count(), 2 * n);
    EXPECT_EQ(simplexSigmaPoints(n).count(), n + 1);
    for (const auto& [name, set] : setsOfDimension(n)) {
      EXPECT_NEAR(set.weights.sum(), 1.0, 1e-14) << name;
      EXPECT_LT((set.unit * set.weights).norm(), 1e-13) << name;
      const Eigen::MatrixXd second = set.unit * set.weights.asDiagonal() * set.unit.transpose();
      EXPECT_LT((second - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-13) << name << " n=" << n;
    }
  }
}

TEST(SigmaPoints, ReproduceMeanAndCovarianceOfRandomSpdMatrices) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (Eigen::Index n : {1, 3, 7, 20}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::MatrixXd P = testing::randomSpd(n, rng);
      Eigen::VectorXd mean(n);
      for (Eigen::Index i = 0; i < n; ++i) mean[i] = g(rng);
      const Eigen::MatrixXd S = P.llt().matrixL();
      for (const auto& [name, set] : setsOfDimension(n)) {
        const Eigen::MatrixXd X = set.points(mean, S);
        EXPECT_LT((set.meanOf(X) - mean).cwiseAbs().maxCoeff(), 1e-12) << name << " n=" << n;
        EXPECT_LT((set.covarianceOf(X) - P).cwiseAbs().maxCoeff(), 1e-12) << name << " n=" << n;
      }
    }
  }
}

// A full-state filter has thousands of entries: the structured products (O(n^2)) and the BLAS
// Gram matrix and Cholesky (above kLargeDense) must equal the plain dense formulas.
TEST(SigmaPoints, StructuredPointsAndLargeKernelsEqualTheDenseFormulas) {
  std::mt19937 rng(8);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Index n = kLargeDense + 57;
  const Eigen::MatrixXd P = testing::randomSpd(n, rng);
  Eigen::VectorXd mean(n);
  for (Eigen::Index i = 0; i < n; ++i) mean[i] = g(rng);
  Eigen::MatrixXd S;
  ASSERT_TRUE(choleskyLower(P, S));
  const Eigen::MatrixXd eigenL = P.llt().matrixL();
  EXPECT_LT((S - eigenL).cwiseAbs().maxCoeff(), 1e-10 * eigenL.cwiseAbs().maxCoeff());
  for (const auto& [name, set] : setsOfDimension(n)) {
    EXPECT_NE(set.structure, UnitStructure::Dense) << name;
    const Eigen::MatrixXd X = set.points(mean, S);
    const Eigen::MatrixXd dense = (S * set.unit).colwise() + mean;
    EXPECT_LT((X - dense).cwiseAbs().maxCoeff(), 1e-11 * dense.cwiseAbs().maxCoeff()) << name;
    const Eigen::MatrixXd D = X.colwise() - set.meanOf(X);
    Eigen::MatrixXd gram;
    weightedGram(D, set.weights, gram);
    const Eigen::MatrixXd reference = D * set.weights.asDiagonal() * D.transpose();
    EXPECT_LT((gram - reference).cwiseAbs().maxCoeff(), 1e-11 * P.cwiseAbs().maxCoeff()) << name;
    EXPECT_LT((gram - P).cwiseAbs().maxCoeff(), 1e-9 * P.cwiseAbs().maxCoeff()) << name;
  }
  Eigen::MatrixXd notSpd = P;
  notSpd(n - 1, n - 1) = -1.0;
  EXPECT_FALSE(choleskyLower(notSpd, S));
}

// The UKF's correction on the system BLAS from kLargeDense rows: P_xz = dX W dZ^T, its transpose
// as A dX^T and P -= G^T G equal Eigen's products, and the lower-triangle Gram of a block of
// columns equals the full one.
TEST(SigmaPoints, LargeCorrectionKernelsEqualEigensProducts) {
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Index n = kLargeDense + 31, s = 40, m = 7;
  Eigen::MatrixXd dX(n, s), dZ(m, s), G(m, n);
  for (Eigen::Index i = 0; i < dX.size(); ++i) dX(i) = g(rng);
  for (Eigen::Index i = 0; i < dZ.size(); ++i) dZ(i) = g(rng);
  for (Eigen::Index i = 0; i < G.size(); ++i) G(i) = g(rng);
  const Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(s, 0.5, 1.5) / s;
  const Eigen::MatrixXd right = w.asDiagonal() * dZ.transpose();
  Eigen::MatrixXd Pxz;
  multiply(dX, right, Pxz);
  const Eigen::MatrixXd PxzEigen = dX * right;
  EXPECT_LT((Pxz - PxzEigen).cwiseAbs().maxCoeff(), 1e-13 * PxzEigen.cwiseAbs().maxCoeff());
  // G = H dX^T (a distributed UKF's gain share), dX read in place, and with no columns: zero.
  Eigen::MatrixXd Gt;
  multiplyByTranspose(right.transpose(), dX, Gt);
  EXPECT_LT((Gt - PxzEigen.transpose()).cwiseAbs().maxCoeff(),
            1e-13 * PxzEigen.cwiseAbs().maxCoeff());
  multiplyByTranspose(Eigen::MatrixXd(m, 0), Eigen::MatrixXd(n, 0), Gt);
  EXPECT_EQ(Gt, Eigen::MatrixXd::Zero(m, n));

  Eigen::MatrixXd P = testing::randomSpd(n, rng), PEigen = P;
  subtractGram(G, P);
  PEigen -= G.transpose() * G;
  EXPECT_LT((P - PEigen).cwiseAbs().maxCoeff(), 1e-13 * PEigen.cwiseAbs().maxCoeff());
  EXPECT_EQ(P, P.transpose());

  Eigen::MatrixXd lower, full;
  weightedGramLower(dX.middleCols(5, 20), w.segment(5, 20), lower);
  weightedGram(dX.middleCols(5, 20), w.segment(5, 20), full);
  EXPECT_EQ(Eigen::MatrixXd(lower.triangularView<Eigen::Lower>()),
            Eigen::MatrixXd(full.triangularView<Eigen::Lower>()));
  EXPECT_EQ(full, full.transpose());
}

TEST(SigmaPoints, SimplexPointsAreEquidistantFromTheMean) {
  const SigmaPointSet set = simplexSigmaPoints(6);
  const double r = set.unit.col(0).norm();
  for (Eigen::Index k = 1; k < set.count(); ++k) EXPECT_NEAR(set.unit.col(k).norm(), r, 1e-12);
}

TEST(SigmaPoints, StarCentreComesFirstAndKindsParse) {
  EXPECT_EQ(starSigmaPoints(4).unit.col(0).norm(), 0.0);
  EXPECT_EQ(parseSigmaPointKind("star"), SigmaPointKind::Star);
  EXPECT_EQ(parseSigmaPointKind("canonical"), SigmaPointKind::Canonical);
  EXPECT_EQ(parseSigmaPointKind("simplex"), SigmaPointKind::Simplex);
  EXPECT_THROW(parseSigmaPointKind("Simplex"), InputError);
  EXPECT_THROW(simplexSigmaPoints(0), InputError);
  EXPECT_THROW(starSigmaPoints(3, -1.0), InputError);
}

}  // namespace
}  // namespace bcassim
