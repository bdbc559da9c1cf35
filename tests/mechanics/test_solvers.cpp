// Linear solvers: every solver reproduces a known solution; PCG preconditioned by a stored
// factorisation matches the direct solution; refresh policy; concurrent and block solves; errors.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>
#include <Eigen/LU>
#include <algorithm>
#include <cstdio>
#include <ostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/mechanics/solvers/CgSolver.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/CholmodSolver.h"
#include "bcassim/mechanics/solvers/ConjugateGradient.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mechanics/solvers/JacobiPcgSolver.h"
#include "bcassim/mechanics/solvers/LinearSolveError.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// 7-point Laplacian of an n^3 grid (Dirichlet outside, so SPD) coupled by an SPD 3x3 block per
// node pair, plus shift * I: SPD, both triangles stored, like a stiffness matrix with 3 dofs
// per node. Nodes on the plane z = 0 are fixed: their rows and columns are identity rows.
SparseMatrix laplacian3d(int n, double shift) {
  Mat3 block;
  block << 2.0, 0.5, 0.2, 0.5, 2.0, 0.3, 0.2, 0.3, 2.0;
  auto id = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  Triplets t;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const int a = id(i, j, k);
        const bool fixedA = k == 0;
        auto add = [&](int b, double w) {
          if (fixedA || b < n * n) return;  // fixed nodes are b < n*n (plane z = 0)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) t.emplace_back(3 * a + r, 3 * b + c, w * block(r, c));
        };
        for (int d = 0; d < 3; ++d) {
          t.emplace_back(3 * a + d, 3 * a + d, fixedA ? 1.0 : shift);
        }
        add(a, 6.0);
        if (i > 0) add(id(i - 1, j, k), -1.0);
        if (i + 1 < n) add(id(i + 1, j, k), -1.0);
        if (j > 0) add(id(i, j - 1, k), -1.0);
        if (j + 1 < n) add(id(i, j + 1, k), -1.0);
        if (k > 0) add(id(i, j, k - 1), -1.0);
        if (k + 1 < n) add(id(i, j, k + 1), -1.0);
      }
    }
  }
  SparseMatrix A(3 * n * n * n, 3 * n * n * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// Random symmetric sparse matrix made SPD by strict diagonal dominance. Entries lie within a
// band of 100 columns, as in a mesh with a locality-preserving node order, so that the Cholesky
// factor does not fill in completely.
SparseMatrix randomSpd(int size, int entriesPerRow, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> offset(-50, 50);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Triplets t;
  Eigen::VectorXd rowSum = Eigen::VectorXd::Zero(size);
  for (int i = 0; i < size; ++i) {
    for (int e = 0; e < entriesPerRow / 2; ++e) {
      const int j = i + offset(rng);
      if (j == i || j < 0 || j >= size) continue;
      const double v = value(rng);
      t.emplace_back(i, j, v);
      t.emplace_back(j, i, v);
      rowSum[i] += std::abs(v);
      rowSum[j] += std::abs(v);
    }
  }
  for (int i = 0; i < size; ++i) t.emplace_back(i, i, rowSum[i] + 0.1);
  SparseMatrix A(size, size);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// S A S + amount * sum over stored pairs i<j of w_ij |a_ij| (e_i - e_j)(e_i - e_j)^T with
// S = diag(1 + amount * u_i), u and w uniform in [-1, 1] and [0, 1]: a symmetric change of
// diagonal and off-diagonal entries by about `amount`, same pattern, still SPD.
SparseMatrix perturb(const SparseMatrix& A, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> w(0.0, 1.0);
  Eigen::VectorXd s(A.rows());
  for (Eigen::Index i = 0; i < s.size(); ++i) s[i] = 1.0 + amount * u(rng);
  SparseMatrix B = s.asDiagonal() * A * s.asDiagonal();
  Eigen::VectorXd diagonalAdd = Eigen::VectorXd::Zero(A.rows());
  for (int j = 0; j < B.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(B, j); it; ++it) {
      if (it.row() <= j) continue;  // lower triangle, mirrored below
      const double c = amount * w(rng) * std::abs(A.coeff(it.row(), j));
      it.valueRef() -= c;
      B.coeffRef(j, it.row()) -= c;
      diagonalAdd[j] += c;
      diagonalAdd[it.row()] += c;
    }
  }
  for (Eigen::Index i = 0; i < B.rows(); ++i) B.coeffRef(i, i) += diagonalAdd[i];
  return B;
}

Eigen::VectorXd randomVector(Eigen::Index size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = u(rng);
  return v;
}

double relativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

Eigen::VectorXd directSolve(const SparseMatrix& A, const Eigen::VectorXd& b) {
  CholmodSolver direct;
  direct.analyzePattern(A);
  direct.setMatrix(A);
  Eigen::VectorXd x;
  direct.solve(b, x);
  return x;
}

// --- one harness for every solver ------------------------------------------------------------

struct HarnessCase {
  std::string solver;
  std::string matrix;
};

void PrintTo(const HarnessCase& c, std::ostream* out) { *out << c.solver << " on " << c.matrix; }

class SolverHarness : public ::testing::TestWithParam<HarnessCase> {};

TEST_P(SolverHarness, ReproducesKnownSolution) {
  const auto& [solverName, matrixName] = GetParam();
  const SparseMatrix A = matrixName == "laplacian" ? laplacian3d(10, 0.1) : randomSpd(3000, 12, 7);
  const Eigen::VectorXd xStar = randomVector(A.rows(), 1);
  const Eigen::VectorXd b = A * xStar;

  RefreshPolicy policy;
  policy.relTol = 1e-13;
  auto solver = makeLinearSolver(solverName, policy);
  EXPECT_EQ(solver->name(), solverName);
  solver->analyzePattern(A);
  solver->setMatrix(A);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  const SolveStatus status = solver->solve(b, x);
  EXPECT_TRUE(status.converged);
  EXPECT_LE(relativeError(x, xStar), 1e-8);
  EXPECT_LE((b - A * x).norm() / b.norm(), 1e-12);
}

std::vector<HarnessCase> harnessCases() {
  std::vector<HarnessCase> cases;
  for (const char* s : {"cg", "jacobi-pcg", "cholmod", "factorized-pcg"})
    for (const char* m : {"laplacian", "random"}) cases.push_back({s, m});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, SolverHarness, ::testing::ValuesIn(harnessCases()),
                         [](const auto& info) {
                           std::string name = info.param.solver + "_" + info.param.matrix;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// --- conjugate gradients ---------------------------------------------------------------------

TEST(SolverCg, ZeroRightHandSideGivesZeroWithoutIterations) {
  const SparseMatrix A = laplacian3d(4, 0.1);
  Eigen::VectorXd x = randomVector(A.rows(), 3);
  const SolveStatus status =
      preconditionedCg(A, Eigen::VectorXd::Zero(A.rows()), x, IdentityPreconditioner(), 1e-10, 10);
  EXPECT_TRUE(status.converged);
  EXPECT_EQ(status.iterations, 0);
  EXPECT_EQ(x.norm(), 0.0);
}

TEST(SolverCg, ReportsNonConvergenceAtIterationLimit) {
  const SparseMatrix A = laplacian3d(8, 0.1);
  const Eigen::VectorXd b = randomVector(A.rows(), 4);
  Eigen::VectorXd x;
  const SolveStatus status = preconditionedCg(A, b, x, IdentityPreconditioner(), 1e-12, 5);
  EXPECT_FALSE(status.converged);
  EXPECT_EQ(status.iterations, 5);
  EXPECT_NEAR(status.relativeResidual, (b - A * x).norm() / b.norm(), 1e-14);
}

// A solver that stops short of its tolerance throws instead of returning its last iterate; the
// message names it, its iterations and the relative residual that iterate really has.
TEST(SolverCg, SolversStoppingShortOfTheToleranceThrowTheExactError) {
  const SparseMatrix A = laplacian3d(8, 0.1);
  const Eigen::VectorXd b = randomVector(A.rows(), 4);
  CgSolver cg(1e-10, 2);
  JacobiPcgSolver jacobi(1e-10, 2);
  for (LinearSolver* solver : std::vector<LinearSolver*>{&cg, &jacobi}) {
    SCOPED_TRACE(solver->name());
    solver->setMatrix(A);
    Eigen::VectorXd x;
    try {
      solver->solve(b, x);
      ADD_FAILURE() << "no LinearSolveError";
    } catch (const LinearSolveError& e) {
      const SolveStatus& status = e.status();
      EXPECT_FALSE(status.converged);
      EXPECT_EQ(status.iterations, 2);
      EXPECT_NEAR(status.relativeResidual, (b - A * x).norm() / b.norm(), 1e-14);
      EXPECT_GT(status.relativeResidual, 1e-3);
      EXPECT_EQ(std::string(e.what()),
                fmt::format("{} did not converge: relative residual {:.3g} after 2 iterations "
                            "(tolerance 1e-10)",
                            solver->name(), status.relativeResidual));
    }
  }
}

TEST(SolverCg, IndefiniteMatrixThrowsNumericalError) {
  SparseMatrix A = laplacian3d(4, 0.1);
  A.diagonal() *= -1.0;  // negative definite on the free dofs
  const Eigen::VectorXd b = randomVector(A.rows(), 5);
  Eigen::VectorXd x;
  EXPECT_THROW(preconditionedCg(A, b, x, IdentityPreconditioner(), 1e-10, 100), NumericalError);
}

// --- PCG with a stored factorisation ---------------------------------------------------------

TEST(SolverFactorizedPcg, ReusedFactorizationGivesDirectSolution) {
  const SparseMatrix A0 = laplacian3d(14, 0.05);
  const SparseMatrix A1 = perturb(A0, 0.05, 11);
  const Eigen::VectorXd b = randomVector(A0.rows(), 12);
  const Eigen::VectorXd xDirect = directSolve(A1, b);

  RefreshPolicy policy;
  policy.relTol = 1e-12;
  FactorizedPcgSolver pcg(policy);
  pcg.analyzePattern(A0);
  pcg.setMatrix(A0);  // factorises A0
  pcg.setMatrix(A1);  // keeps the factor of A0
  EXPECT_EQ(pcg.factorizations(), 1);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A1.rows());
  const SolveStatus reuse = pcg.solve(b, x);
  EXPECT_TRUE(reuse.converged);
  EXPECT_FALSE(reuse.refactorized);
  EXPECT_EQ(pcg.factorizations(), 1);
  EXPECT_LE(relativeError(x, xDirect), 1e-8);

  JacobiPcgSolver jacobi(policy.relTol);
  jacobi.setMatrix(A1);
  Eigen::VectorXd xJacobi = Eigen::VectorXd::Zero(A1.rows());
  const SolveStatus reference = jacobi.solve(b, xJacobi);
  EXPECT_TRUE(reference.converged);
  EXPECT_GT(reuse.iterations, 0);
  EXPECT_LT(3 * reuse.iterations, reference.iterations)
      << "reused factor: " << reuse.iterations << ", Jacobi: " << reference.iterations;
}

TEST(SolverFactorizedPcg, RefreshesEveryNMatrices) {
  const SparseMatrix A0 = laplacian3d(6, 0.1);
  RefreshPolicy policy;
  policy.everyNMatrices = 3;
  policy.maxIterations = 1000;  // never refresh because of iterations
  policy.relTol = 1e-12;
  FactorizedPcgSolver solver(policy);
  solver.analyzePattern(A0);
  std::vector<int> refactorizedAt;
  for (int m = 1; m <= 8; ++m) {
    const SparseMatrix A = perturb(A0, 0.05, 100 + m);
    const int before = solver.factorizations();
    solver.setMatrix(A);
    if (solver.factorizations() > before) refactorizedAt.push_back(m);
    const Eigen::VectorXd b = randomVector(A.rows(), m);
    Eigen::VectorXd x;
    const SolveStatus status = solver.solve(b, x);
    EXPECT_FALSE(status.refactorized);
    EXPECT_LE(relativeError(x, directSolve(A, b)), 1e-8);
  }
  EXPECT_EQ(refactorizedAt, (std::vector<int>{1, 4, 7}));
}

TEST(SolverFactorizedPcg, RefactorizesInsideSolveWhenPcgNeedsTooManyIterations) {
  const SparseMatrix A0 = laplacian3d(8, 0.1);
  const SparseMatrix A1 = perturb(A0, 0.5, 21);
  const Eigen::VectorXd b = randomVector(A0.rows(), 22);
  RefreshPolicy policy;
  policy.maxIterations = 1;
  policy.singlePrecision = false;  // the exact factor must then converge in one iteration
  FactorizedPcgSolver solver(policy);
  solver.setMatrix(A0);
  solver.setMatrix(A1);
  Eigen::VectorXd x;
  const SolveStatus status = solver.solve(b, x);
  EXPECT_TRUE(status.refactorized);
  EXPECT_TRUE(status.converged);
  EXPECT_EQ(solver.factorizations(), 2);
  EXPECT_LE(relativeError(x, directSolve(A1, b)), 1e-12);

  // The fresh factor is exact for A1: the next solve needs no refresh.
  Eigen::VectorXd y;
  const SolveStatus next = solver.solve(randomVector(A0.rows(), 23), y);
  EXPECT_FALSE(next.refactorized);
  EXPECT_LE(next.iterations, 1);
}

// A tolerance below round-off: the stored factor does not reach it, nor does A's own; the solve
// is an error after both tries, not the second try's iterate.
TEST(SolverFactorizedPcg, UnreachableToleranceIsAnErrorEvenWithAFreshFactor) {
  const SparseMatrix A = laplacian3d(6, 0.1);
  const Eigen::VectorXd b = randomVector(A.rows(), 41);
  RefreshPolicy policy;
  policy.relTol = 1e-20;
  policy.maxIterations = 4;
  FactorizedPcgSolver solver(policy);
  solver.setMatrix(A);
  Eigen::VectorXd x;
  try {
    solver.solve(b, x);
    ADD_FAILURE() << "no LinearSolveError";
  } catch (const LinearSolveError& e) {
    EXPECT_TRUE(e.status().refactorized);
    EXPECT_EQ(e.status().iterations, 8);  // both tries
    EXPECT_EQ(solver.factorizations(), 2);
    EXPECT_EQ(std::string(e.what()),
              fmt::format("factorized-pcg did not converge: relative residual {:.3g} after 8 "
                          "iterations (tolerance 1e-20), even with A itself factorised",
                          e.status().relativeResidual));
  }
}

TEST(SolverFactorizedPcg, SharedFactorIsUsedAndNeverModified) {
  const SparseMatrix A0 = laplacian3d(8, 0.1);
  const SparseMatrix A1 = perturb(A0, 0.05, 31);
  const SparseMatrix A2 = perturb(A0, 0.5, 32);
  const Eigen::VectorXd b = randomVector(A0.rows(), 33);

  FactorizedPcgSolver owner;
  owner.setMatrix(A0);
  const std::shared_ptr<CholeskyFactor> shared = owner.factor();
  RefreshPolicy policy;
  policy.maxIterations = 3;
  FactorizedPcgSolver sigma(shared, policy);
  sigma.analyzePattern(A1);  // same pattern: keeps the shared factor
  sigma.setMatrix(A1);
  EXPECT_EQ(sigma.factorizations(), 0);
  EXPECT_EQ(sigma.factor(), shared);

  sigma.setMatrix(A2);  // too far from A0: the solve refreshes into a factor of its own
  Eigen::VectorXd x;
  EXPECT_TRUE(sigma.solve(b, x).refactorized);
  EXPECT_NE(sigma.factor(), shared);
  EXPECT_EQ(owner.factor(), shared);
  Eigen::VectorXd x0;
  shared->solve(b, x0);  // still the factor of A0
  EXPECT_LE(relativeError(x0, directSolve(A0, b)), 1e-12);
}

// --- the shared factor across threads --------------------------------------------------------

TEST(SolverCholeskyFactor, ConcurrentSolvesMatchSequentialOnes) {
  const SparseMatrix A = laplacian3d(12, 0.1);
  auto factor = std::make_shared<CholeskyFactor>();
  factor->analyzePattern(A);
  factor->factorize(A);

  constexpr int kThreads = 4;
  constexpr int kSolvesPerThread = 6;
  std::vector<std::vector<Eigen::VectorXd>> rhs(kThreads), sequential(kThreads),
      concurrent(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    for (int s = 0; s < kSolvesPerThread; ++s) {
      rhs[t].push_back(randomVector(A.rows(), 1000 * t + s));
      Eigen::VectorXd x;
      factor->solve(rhs[t].back(), x);
      sequential[t].push_back(x);
    }
  }
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      CholeskyFactor::Workspace work;  // odd threads reuse a workspace, even ones use none
      for (int s = 0; s < kSolvesPerThread; ++s) {
        Eigen::VectorXd x;
        if (t % 2) {
          factor->solve(rhs[t][s], x, work);
        } else {
          factor->solve(rhs[t][s], x);
        }
        concurrent[t].push_back(x);
      }
    });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) {
    for (int s = 0; s < kSolvesPerThread; ++s) {
      EXPECT_EQ(concurrent[t][s], sequential[t][s]) << "thread " << t << ", solve " << s;
      EXPECT_LE((A * concurrent[t][s] - rhs[t][s]).norm() / rhs[t][s].norm(), 1e-12);
    }
  }
}

TEST(SolverCholeskyFactor, SigmaPointSolversShareOneFactorConcurrently) {
  const SparseMatrix A0 = laplacian3d(10, 0.1);
  FactorizedPcgSolver first;
  first.setMatrix(A0);

  constexpr int kThreads = 3;
  std::vector<SparseMatrix> matrices;
  std::vector<Eigen::VectorXd> rhs, results(kThreads);
  std::vector<SolveStatus> statuses(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    matrices.push_back(perturb(A0, 0.05, 40 + t));
    rhs.push_back(randomVector(A0.rows(), 50 + t));
  }
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      FactorizedPcgSolver sigma(first.factor());
      sigma.setMatrix(matrices[t]);
      statuses[t] = sigma.solve(rhs[t], results[t]);
    });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_TRUE(statuses[t].converged);
    EXPECT_FALSE(statuses[t].refactorized);
    EXPECT_LE(relativeError(results[t], directSolve(matrices[t], rhs[t])), 1e-8);
  }
}

TEST(SolverCholeskyFactor, BlockSolveEqualsColumnByColumnSolves) {
  const SparseMatrix A = randomSpd(2000, 10, 61);
  CholeskyFactor factor;
  factor.factorize(A);  // analyses on first use
  Eigen::MatrixXd B(A.rows(), 5);
  for (int c = 0; c < B.cols(); ++c) B.col(c) = randomVector(A.rows(), 70 + c);
  Eigen::MatrixXd X;
  factor.solve(B, X);
  ASSERT_EQ(X.rows(), B.rows());
  ASSERT_EQ(X.cols(), B.cols());
  CholeskyFactor::Workspace work;
  for (int c = 0; c < B.cols(); ++c) {
    Eigen::VectorXd x;
    factor.solve(Eigen::VectorXd(B.col(c)), x, work);
    EXPECT_LE(relativeError(X.col(c), x), 1e-14) << "column " << c;
    EXPECT_LE((A * x - B.col(c)).norm() / B.col(c).norm(), 1e-12);
  }
}

// Node-block SPD matrix: a 3x3 SPD block per pair of neighbours on a ring of nodes with random
// chords (every column triple shares one row pattern, as in an FEM matrix), diagonally dominant.
SparseMatrix nodeBlockSpd(int nodes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> other(0, nodes - 1);
  Mat3 block;
  block << 2.0, 0.5, 0.2, 0.5, 2.0, 0.3, 0.2, 0.3, 2.0;
  Triplets t;
  auto couple = [&](int a, int b) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        t.emplace_back(3 * a + r, 3 * b + c, -block(r, c));
        t.emplace_back(3 * b + r, 3 * a + c, -block(c, r));
        t.emplace_back(3 * a + r, 3 * a + c, block(r, c));
        t.emplace_back(3 * b + r, 3 * b + c, block(r, c));
      }
  };
  for (int a = 0; a < nodes; ++a) {
    couple(a, (a + 1) % nodes);
    const int b = other(rng);
    if (b != a) couple(a, b);
    for (int d = 0; d < 3; ++d) t.emplace_back(3 * a + d, 3 * a + d, 0.05);
  }
  SparseMatrix A(3 * nodes, 3 * nodes);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(SolverCg, NodeBlockAndGeneralPatternsGiveTheDirectSolution) {
  // The product with A takes a faster path when column triples share their pattern; a single
  // extra entry breaks the sharing and must give the same answer by the general path.
  const SparseMatrix blocked = nodeBlockSpd(300, 91);
  SparseMatrix general = blocked;
  general.coeffRef(0, 4) += 1e-3;
  general.coeffRef(4, 0) += 1e-3;
  general.makeCompressed();
  for (const SparseMatrix* A : std::vector<const SparseMatrix*>{&blocked, &general}) {
    const Eigen::VectorXd b = randomVector(A->rows(), 92);
    JacobiPcgSolver cg(1e-12);
    cg.setMatrix(*A);
    Eigen::VectorXd x;
    const SolveStatus status = cg.solve(b, x);
    EXPECT_TRUE(status.converged);
    EXPECT_LE(relativeError(x, directSolve(*A, b)), 1e-9);
    EXPECT_LE((*A * x - b).norm() / b.norm(), 1e-12);
  }
}

TEST(SolverCholeskyFactor, SupernodalSweepsMatchCholmodInDoubleAndApproximateItInSingle) {
  const SparseMatrix A = laplacian3d(12, 0.05);
  CholeskyFactor factor;
  factor.factorize(A);
  const Eigen::VectorXd b = randomVector(A.rows(), 81);
  CholeskyFactor::Workspace work;
  Eigen::VectorXd x, xDouble, xSingle;
  factor.solve(b, x, work);
  factor.solveSupernodalDouble(b, xDouble, work);
  factor.solveSinglePrecision(b, xSingle, work);
  EXPECT_LE(relativeError(xDouble, x), 1e-13);
  const double singleError = relativeError(xSingle, x);
  EXPECT_GT(singleError, 1e-12) << "the single-precision path computed in double";
  EXPECT_LE(singleError, 1e-4);
  // A refactorisation replaces the float copy: the single-precision solve follows the new matrix.
  const SparseMatrix A2 = perturb(A, 0.3, 82);
  factor.factorize(A2);
  factor.solveSinglePrecision(b, xSingle, work);
  EXPECT_LE(relativeError(xSingle, directSolve(A2, b)), 1e-4);
}

// A released factor's values and float copy serve the next factorisation of its analysis (the
// spares): the float copy a clone then makes is its own matrix's, not the released one's.
TEST(SolverCholeskyFactor, AFloatCopyMadeFromTheSparesIsTheNewFactors) {
  const SparseMatrix A = laplacian3d(12, 0.05);
  const SparseMatrix A2 = perturb(A, 0.3, 84);
  const Eigen::VectorXd b = randomVector(A.rows(), 85);
  const Eigen::VectorXd x1 = directSolve(A, b), x2 = directSolve(A2, b);
  ASSERT_GT(relativeError(x2, x1), 1e-2);
  CholeskyFactor::Workspace work;
  Eigen::VectorXd x;
  auto first = std::make_shared<CholeskyFactor>();
  first->factorize(A);
  first->solveSinglePrecision(b, x, work);
  EXPECT_LE(relativeError(x, x1), 1e-4);
  const std::shared_ptr<CholeskyFactor> second = first->cloneAnalysis();
  first.reset();
  second->factorize(A2);
  second->solveSinglePrecision(b, x, work);
  EXPECT_LE(relativeError(x, x2), 1e-4);
}

// A solver made from another factor's analysis (makeLinearSolver's `analysis`) solves its own
// matrices of that pattern, and analyses a matrix of another pattern anew.
TEST(SolverCholmod, StartsFromAnotherFactorsAnalysis) {
  const SparseMatrix A = laplacian3d(10, 0.05);
  CholeskyFactor analysed;
  analysed.factorize(A);
  for (const char* name : {"cholmod", "factorized-pcg"}) {
    std::unique_ptr<LinearSolver> solver = makeLinearSolver(name, {}, &analysed);
    const SparseMatrix A2 = perturb(A, 0.3, 86);
    solver->analyzePattern(A2);
    solver->setMatrix(A2);
    const Eigen::VectorXd b = randomVector(A.rows(), 87);
    Eigen::VectorXd x;
    solver->solve(b, x);
    EXPECT_LE(relativeError(x, directSolve(A2, b)), 1e-9) << name;
    const SparseMatrix B = laplacian3d(8, 0.1);
    solver->analyzePattern(B);
    solver->setMatrix(B);
    const Eigen::VectorXd c = randomVector(B.rows(), 88);
    solver->solve(c, x);
    EXPECT_LE(relativeError(x, directSolve(B, c)), 1e-9) << name;
  }
  // The analysed factor itself is untouched.
  const Eigen::VectorXd b = randomVector(A.rows(), 89);
  Eigen::VectorXd x;
  analysed.solve(b, x);
  EXPECT_LE(relativeError(x, directSolve(A, b)), 1e-12);
}

// The sweeps split into subtrees of the elimination tree (Workspace::setThreads): a 16^3
// Laplacian's tree splits into groups and its top separators are large enough to be cut into
// pieces too. Every thread count gives the same bits; the result is the serial sweep's to
// round-off (not bit for bit: the groups' updates of the top rows are summed in another order).
TEST(SolverCholeskyFactor, SplitSweepsGiveTheSameBitsOnAnyNumberOfThreads) {
  const SparseMatrix A = laplacian3d(16, 0.05);
  CholeskyFactor factor;
  factor.factorize(A);
  const Eigen::VectorXd b = randomVector(A.rows(), 83);
  Eigen::VectorXd exact, serialSingle, serialDouble;
  factor.solve(b, exact);
  CholeskyFactor::Workspace serial;
  factor.solveSinglePrecision(b, serialSingle, serial);
  factor.solveSupernodalDouble(b, serialDouble, serial);
  Eigen::VectorXd single1, double1;
  for (int threads : {1, 2, 3}) {
    CholeskyFactor::Workspace work;
    work.setThreads(threads);
    Eigen::VectorXd xs, xd;
    factor.solveSinglePrecision(b, xs, work);
    factor.solveSupernodalDouble(b, xd, work);
    EXPECT_LE(relativeError(xd, exact), 1e-13) << threads;
    EXPECT_LE(relativeError(xs, exact), 1e-4) << threads;
    EXPECT_LE(relativeError(xs, serialSingle), 1e-5) << threads;
    if (threads == 1) {
      single1 = xs;
      double1 = xd;
      // Another order of sums: were the split a copy of the serial sweep, this would be 0.
      EXPECT_GT((xs - serialSingle).cwiseAbs().maxCoeff(), 0.0);
    } else {
      EXPECT_EQ((xs - single1).cwiseAbs().maxCoeff(), 0.0) << threads;
      EXPECT_EQ((xd - double1).cwiseAbs().maxCoeff(), 0.0) << threads;
    }
  }
  // A factor of a few supernodes (a tree too small to split) solves the same way.
  const SparseMatrix small = laplacian3d(3, 0.5);
  CholeskyFactor smallFactor;
  smallFactor.factorize(small);
  CholeskyFactor::Workspace work;
  work.setThreads(2);
  Eigen::VectorXd x;
  const Eigen::VectorXd bs = randomVector(small.rows(), 84);
  smallFactor.solveSupernodalDouble(bs, x, work);
  EXPECT_LE(relativeError(x, directSolve(small, bs)), 1e-13);
  EXPECT_THROW(work.setThreads(-1), std::invalid_argument);
}

// The analysis tries several fill-reducing orderings and keeps the best: on a 3D grid with 3 dofs
// per node (a tet mesh's pattern) the factor is smaller than with AMD, CHOLMOD's default choice
// there, alone.
TEST(SolverCholeskyFactor, AnalysisKeepsASparserFactorThanAmdAlone) {
  const SparseMatrix A = laplacian3d(16, 0.05);
  CholeskyFactor factor;
  factor.analyzePattern(A);
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.supernodal = CHOLMOD_SUPERNODAL;
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_AMD;
  cholmod_sparse view = Eigen::viewAsCholmod(A.selfadjointView<Eigen::Lower>());
  cholmod_factor* amd = cholmod_analyze(&view, &c);
  ASSERT_NE(amd, nullptr);
  const double amdNonZeros = c.lnz;
  cholmod_free_factor(&amd, &c);
  cholmod_finish(&c);
  std::printf("entries in L: %lld kept, %.0f with AMD\n",
              static_cast<long long>(factor.factorNonZeros()), amdNonZeros);
  EXPECT_LT(static_cast<double>(factor.factorNonZeros()), 0.95 * amdNonZeros);
}

// A low-rank update (A + B C B^T) solved through the forward half of a block solve: W = L^-1 P B
// lives on the elimination-tree paths of B's few non-zero rows only, G = W^T W = B^T A^-1 B, and
// the Woodbury correction applied between the sweeps gives the updated system's solution.
TEST(SolverCholeskyFactor, ForwardSolveAlongPathsGivesWoodburyUpdatesBetweenTheSweeps) {
  const SparseMatrix A = laplacian3d(16, 0.05);
  const auto n = A.rows();
  CholeskyFactor factor;
  factor.factorize(A);
  // Two "springs", each spreading 3 components over 4 nearby dofs, as a spring's attachment does.
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, 6);
  const int anchors[2] = {137, 2901};
  for (int s = 0; s < 2; ++s)
    for (int c = 0; c < 3; ++c)
      for (int a = 0; a < 4; ++a) B(anchors[s] + 3 * a + c, 3 * s + c) = 0.1 + 0.2 * a;
  std::vector<int> rows;
  Eigen::MatrixXd W;
  factor.forwardSolve(B, rows, W);
  ASSERT_EQ(W.rows(), static_cast<Eigen::Index>(rows.size()));
  ASSERT_EQ(W.cols(), B.cols());
  EXPECT_LT(static_cast<Eigen::Index>(rows.size()), n / 2) << "the paths are most of the tree";
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end()));
  Eigen::MatrixXd AinvB;
  factor.solve(B, AinvB);
  const Eigen::MatrixXd G = W.transpose() * W, exactG = B.transpose() * AinvB;
  EXPECT_LE((G - exactG).norm(), 1e-12 * exactG.norm());

  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
  C.block<3, 3>(0, 0) << 3.0, 0.5, 0.0, 0.5, 2.0, 0.1, 0.0, 0.1, 1.0;
  C.block<3, 3>(3, 3) = -0.5 * C.block<3, 3>(0, 0);  // a spring made softer: still SPD here
  const SparseMatrix Bs = B.sparseView();
  const SparseMatrix updated =
      A + SparseMatrix(Bs * SparseMatrix(C.sparseView()) * SparseMatrix(Bs.transpose()));
  const Eigen::VectorXd b = randomVector(n, 85);
  const Eigen::VectorXd exact = directSolve(updated, b);
  const auto lu = (Eigen::MatrixXd::Identity(6, 6) + C * G).partialPivLu();
  const CholeskyFactor::MidCorrection woodbury = [&](Eigen::VectorXd& c) {
    Eigen::VectorXd onPaths(W.rows());
    for (size_t r = 0; r < rows.size(); ++r) onPaths(static_cast<Eigen::Index>(r)) = c(rows[r]);
    onPaths = W * lu.solve(C * (W.transpose() * onPaths));
    for (size_t r = 0; r < rows.size(); ++r) c(rows[r]) -= onPaths(static_cast<Eigen::Index>(r));
  };
  for (int threads : {0, 2}) {
    CholeskyFactor::Workspace work;
    work.setThreads(threads);
    Eigen::VectorXd x;
    factor.solveWithMidCorrection(b, x, work, false, woodbury);
    EXPECT_LE(relativeError(x, exact), 1e-12) << threads;
    factor.solveWithMidCorrection(b, x, work, true, woodbury);
    EXPECT_LE(relativeError(x, exact), 1e-4) << threads;
    factor.solveWithMidCorrection(b, x, work, false, [](Eigen::VectorXd&) {});
    EXPECT_LE(relativeError(x, directSolve(A, b)), 1e-12) << threads;
  }
  EXPECT_THROW(factor.forwardSolve(Eigen::MatrixXd::Zero(n - 1, 2), rows, W),
               std::invalid_argument);
}

TEST(SolverFactorizedPcg, SinglePrecisionPreconditionerStillConvergesInDouble) {
  const SparseMatrix A0 = laplacian3d(14, 0.05);
  const SparseMatrix A1 = perturb(A0, 0.05, 11);
  const Eigen::VectorXd b = randomVector(A0.rows(), 12);
  int iterations[2] = {0, 0};
  for (bool single : {false, true}) {
    RefreshPolicy policy;
    policy.relTol = 1e-12;
    policy.singlePrecision = single;
    FactorizedPcgSolver pcg(policy);
    pcg.setMatrix(A0);
    pcg.setMatrix(A1);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(A1.rows());
    const SolveStatus status = pcg.solve(b, x);
    EXPECT_TRUE(status.converged);
    EXPECT_FALSE(status.refactorized);
    EXPECT_LE(relativeError(x, directSolve(A1, b)), 1e-9);
    iterations[single] = status.iterations;
  }
  // Rounding L to float perturbs the preconditioner far less than the change from A0 to A1.
  EXPECT_LE(iterations[1], iterations[0] + 1);
}

// --- errors ----------------------------------------------------------------------------------

TEST(SolverCholmod, NonPositiveDefiniteMatrixThrowsNumericalError) {
  const SparseMatrix spd = laplacian3d(5, 0.1);
  SparseMatrix indefinite = spd;
  indefinite.coeffRef(200, 200) = -1.0;
  CholmodSolver solver;
  solver.analyzePattern(indefinite);
  EXPECT_THROW(solver.setMatrix(indefinite), NumericalError);

  // The solver recovers with a positive definite matrix of the same pattern.
  solver.setMatrix(spd);
  const Eigen::VectorXd xStar = randomVector(spd.rows(), 81);
  Eigen::VectorXd x;
  solver.solve(spd * xStar, x);
  EXPECT_LE(relativeError(x, xStar), 1e-10);
}

TEST(SolverFactory, UnknownNameThrowsInputErrorNamingTheChoices) {
  try {
    makeLinearSolver("lu");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "unknown linear solver 'lu'; expected one of cg, jacobi-pcg, cholmod, "
                 "factorized-pcg");
  }
}

}  // namespace
}  // namespace bcassim
