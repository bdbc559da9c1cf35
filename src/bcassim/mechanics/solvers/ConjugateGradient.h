// Preconditioned conjugate gradients for symmetric positive definite sparse systems, as a free
// function over a preconditioner interface, with a reusable workspace so iterations never allocate.
#pragma once
#include "bcassim/Types.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

// z = M^{-1} r for a symmetric positive definite approximation M of A. An instance may keep
// scratch memory, so one instance serves one thread at a time.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const = 0;
};

// M = I: plain conjugate gradients.
class IdentityPreconditioner final : public Preconditioner {
 public:
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override { z = r; }
};

// M = diag(A). The diagonal must be positive (throws NumericalError otherwise).
class JacobiPreconditioner final : public Preconditioner {
 public:
  JacobiPreconditioner() = default;
  explicit JacobiPreconditioner(const SparseMatrix& A) { compute(A); }
  void compute(const SparseMatrix& A);
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override {
    z = invDiagonal_.cwiseProduct(r);
  }

 private:
  Eigen::VectorXd invDiagonal_;
};

// Vectors PCG needs besides x; sized on first use and reused, so a solver that keeps one performs
// no allocation per iteration (nor per solve once the size is fixed).
struct CgWorkspace {
  Eigen::VectorXd r, z, p, Ap;
};

// Solves A x = b (A symmetric positive definite) by PCG with preconditioner M, starting from x
// (a vector of the wrong size is replaced by zeros). Stops when |b - A x| / |b| <= relTol,
// confirmed on the true residual, or after maxIter iterations (status.converged = false).
// Single-threaded: sigma points already run in parallel. Throws NumericalError if a search
// direction with p'Ap <= 0 shows that A (or M) is not positive definite.
SolveStatus preconditionedCg(const SparseMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             const Preconditioner& M, double relTol, int maxIter,
                             CgWorkspace& work);

// Same with a temporary workspace (allocates once per call).
SolveStatus preconditionedCg(const SparseMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             const Preconditioner& M, double relTol, int maxIter);

}  // namespace bcassim
