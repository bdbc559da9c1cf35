// Sigma points factorise their own matrices at the same time: concurrent CHOLMOD factorisations
// and solves on different threads must give exactly the sequential results (the BLAS under
// CHOLMOD must be safe for concurrent calls: Debian's pthread OpenBLAS is, its serial build is
// not).
#include <gtest/gtest.h>

#include <thread>

#include "FemTestHelpers.h"
#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {
namespace {

SparseMatrix implicitEulerMatrix(double youngModulus) {
  MechanicalModel model =
      testing::boxModel(Vec3(0.15, 0.03, 0.03), 16, 4, 4, makeMaterial("stvk", youngModulus, 0.49));
  Eigen::VectorXd f;
  SparseMatrix K;
  model.internalForcesAndStiffness(0.0, model.restPositions(), f, K);
  K *= 1e-4;  // dt^2
  model.mass.addTo(*model.pattern, 1.0, K);
  return K;
}

TEST(CholeskyFactorThreads, ConcurrentFactorisationsEqualSequentialOnes) {
  const SparseMatrix A = implicitEulerMatrix(8000.0), B = implicitEulerMatrix(12000.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  Eigen::VectorXd xa, xb;
  {
    CholeskyFactor fa, fb;
    fa.factorize(A);
    fb.factorize(B);
    fa.solve(b, xa);
    fb.solve(b, xb);
  }
  for (int round = 0; round < 40; ++round) {
    Eigen::VectorXd ya, yb;
    auto work = [&b](const SparseMatrix& M, Eigen::VectorXd& y) {
      CholeskyFactor factor;
      factor.factorize(M);
      factor.solve(b, y);
    };
    std::thread ta(work, std::cref(A), std::ref(ya));
    std::thread tb(work, std::cref(B), std::ref(yb));
    ta.join();
    tb.join();
    ASSERT_EQ((ya - xa).norm(), 0.0) << "round " << round;
    ASSERT_EQ((yb - xb).norm(), 0.0) << "round " << round;
  }
}

}  // namespace
}  // namespace bcassim

namespace bcassim {
namespace {

// A refresh computed on another thread changes nothing but the preconditioner: the trajectory
// equals the one with a factorisation at every step, to the PCG tolerance. (80 kPa: at 8 kPa the
// beam sags 10 cm under its weight and StVK tets at the clamp invert, an error since they are.)
TEST(FactorizedPcgSolverBackground, TrajectoryEqualsDirectSolves) {
  MechanicalModel model =
      testing::boxModel(Vec3(0.15, 0.03, 0.03), 12, 3, 3, makeMaterial("stvk", 80000.0, 0.45));
  model.dirichlet = DirichletConditions(
      {{testing::nodesWhere(*model.mesh, [](const Vec3& p) { return p.x() < 1e-12; })}},
      *model.pattern);
  model.gravity = Vec3(0, 0, -9.81);
  RefreshPolicy policy;
  policy.everyNMatrices = 3;
  policy.relTol = 1e-12;
  policy.background = true;
  ImplicitEuler reuse(model, makeLinearSolver("factorized-pcg", policy), {0.01, 0, 1e-10});
  ImplicitEuler direct(model, makeLinearSolver("cholmod"), {0.01, 0, 1e-10});
  MechanicalState a = model.restState(), b = model.restState();
  for (int step = 0; step < 40; ++step) {
    reuse.step(model, a);
    direct.step(model, b);
  }
  EXPECT_LT((a.x - b.x).norm(), 1e-9 * (b.x - model.restPositions()).norm());
  auto& solver = dynamic_cast<FactorizedPcgSolver&>(reuse.linearSolver());
  EXPECT_GT(solver.factorizations(), 1);  // background refreshes were adopted
}

}  // namespace
}  // namespace bcassim
