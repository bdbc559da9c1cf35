// bcassim's own numeric supernodal factorisation (SupernodalCholesky, CholeskyFactor::factorize)
// against CHOLMOD's: the same solutions to round-off, the same bits on any number of threads, the
// same error for a matrix that is not positive definite.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "FemTestHelpers.h"
#include "bcassim/Error.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"

namespace bcassim {
namespace {

// A 25 x 7 x 7-node bar (3,675 unknowns): its nested dissection has groups of subtrees and top
// supernodes wide enough to be cut in pieces (> 32 columns) and finished in panels (423 columns:
// four panels of SupernodalCholesky::finishInPanels). Its stiffness stretched by `stretch`
// along the bar plus `massScale` M.
SparseMatrix barMatrix(double poissonRatio, double massScale, double stretch = 1.02) {
  MechanicalModel model = testing::boxModel(Vec3(0.24, 0.06, 0.06), 24, 6, 6,
                                            makeMaterial("neohookean", 5000.0, poissonRatio));
  Eigen::VectorXd f;
  SparseMatrix K;
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < x.size(); i += 3) x(i) *= stretch;  // not the rest tangent
  model.internalForcesAndStiffness(0.0, x, f, K);
  model.mass.addTo(*model.pattern, massScale, K);
  return K;
}

// A 12 x 12 x 12-element cube (6,591 unknowns), stretched along x: four top supernodes of 141 to
// 666 columns, finished in panels.
SparseMatrix cubeMatrix() {
  MechanicalModel model =
      testing::boxModel(Vec3(0.1, 0.1, 0.1), 12, 12, 12, makeMaterial("neohookean", 5000.0, 0.45));
  Eigen::VectorXd f;
  SparseMatrix K;
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < x.size(); i += 3) x(i) *= 1.02;
  model.internalForcesAndStiffness(0.0, x, f, K);
  model.mass.addTo(*model.pattern, 1e2, K);
  return K;
}

Eigen::VectorXd rightHandSide(Eigen::Index n) {
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) b(i) = std::sin(0.37 * static_cast<double>(i)) + 0.1;
  return b;
}

double relativeGap(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(SupernodalCholesky, SolvesLikeCholmodsFactor) {
  const std::pair<const char*, SparseMatrix> matrices[] = {
      {"bar, nu 0.3, 1e4 M", barMatrix(0.3, 1e4)},
      {"bar, nu 0.49, 1e2 M", barMatrix(0.49, 1e2)},
      {"cube", cubeMatrix()}};
  for (const auto& [name, A] : matrices) {
    const Eigen::VectorXd b = rightHandSide(A.rows());
    CholeskyFactor ours, cholmods;
    ours.factorize(A);
    cholmods.factorizeWithCholmod(A);
    Eigen::VectorXd x, y;
    ours.solve(b, x);
    cholmods.solve(b, y);
    EXPECT_LT((A * x - b).norm() / b.norm(), 1e-10) << name;
    EXPECT_LT(relativeGap(x, y), 1e-9) << name;
  }
}

TEST(SupernodalCholesky, SameBitsOnAnyNumberOfThreads) {
  const SparseMatrix A = barMatrix(0.45, 100.0);
  const Eigen::VectorXd b = rightHandSide(A.rows());
  Eigen::VectorXd first;
  for (const SparseMatrix& matrix : {cubeMatrix(), A}) {
    first.resize(0);
    for (int threads : {1, 2, 3, 1}) {
      CholeskyFactor factor;
      factor.factorize(matrix, threads);
      Eigen::VectorXd x;
      factor.solve(rightHandSide(matrix.rows()), x);
      if (first.size() == 0)
        first = x;
      else
        EXPECT_EQ((x - first).cwiseAbs().maxCoeff(), 0.0)
            << threads << " threads, " << matrix.rows() << " unknowns";
    }
  }
  // Refactorising the same object (its values written over) gives them again.
  CholeskyFactor again;
  again.factorize(barMatrix(0.3, 1.0), 2);
  again.factorize(A, 2);
  Eigen::VectorXd x;
  again.solve(b, x);
  EXPECT_EQ((x - first).cwiseAbs().maxCoeff(), 0.0);
}

// The messages of a factorisation of A by ours on 2 threads and by CHOLMOD ("" where it succeeds).
std::pair<std::string, std::string> failures(const SparseMatrix& A) {
  std::string ours, cholmods;
  try {
    CholeskyFactor factor;
    factor.factorize(A, 2);
  } catch (const NumericalError& e) {
    ours = e.what();
  }
  try {
    CholeskyFactor factor;
    factor.factorizeWithCholmod(A);
  } catch (const NumericalError& e) {
    cholmods = e.what();
  }
  return {ours, cholmods};
}

TEST(SupernodalCholesky, NotPositiveDefiniteFailsWithCholmodsMessage) {
  SparseMatrix A = barMatrix(0.45, 100.0);
  const Eigen::Index k = A.rows() / 2;
  A.coeffRef(k, k) = -A.coeffRef(k, k);
  const auto [ours, cholmods] = failures(A);
  EXPECT_NE(ours.find("Cholesky factorisation: matrix is not positive definite (pivot "),
            std::string::npos)
      << ours;
  EXPECT_EQ(ours, cholmods);
  // The failed factor is rebuilt at the next factorisation.
  CholeskyFactor factor;
  EXPECT_THROW(factor.factorize(A), NumericalError);
  EXPECT_FALSE(factor.isFactorized());
  const SparseMatrix B = barMatrix(0.45, 100.0);
  factor.factorize(B);
  Eigen::VectorXd x;
  const Eigen::VectorXd b = rightHandSide(B.rows());
  factor.solve(b, x);
  EXPECT_LT((B * x - b).norm() / b.norm(), 1e-10);
}

// The cube shifted just past its smallest eigenvalue (found by inverse iteration): the lowest
// mode is global, so the first pivot to fail is one of the last separator's, inside its last panel
// (column 661 of 666).
TEST(SupernodalCholesky, APivotFailingInsideAPanelIsCholmodsColumn) {
  const SparseMatrix A = cubeMatrix();
  CholeskyFactor factor;
  factor.factorize(A);
  Eigen::VectorXd v = rightHandSide(A.rows()), w;
  double lambda = 0;
  for (int it = 0; it < 60; ++it) {
    const Eigen::VectorXd unit = v.normalized();
    factor.solve(unit, w);  // w = A^-1 unit: |w| -> 1 / lambda_min
    lambda = (w.dot(unit) > 0 ? 1.0 : -1.0) / w.norm();
    v = w;
  }
  ASSERT_GT(lambda, 0);
  SparseMatrix shift(A.rows(), A.cols());
  shift.setIdentity();
  const SparseMatrix shifted = A - 1.001 * lambda * shift;
  const auto [ours, cholmods] = failures(shifted);
  EXPECT_NE(ours.find("not positive definite (pivot "), std::string::npos) << ours;
  EXPECT_EQ(ours, cholmods);
}

}  // namespace
}  // namespace bcassim
