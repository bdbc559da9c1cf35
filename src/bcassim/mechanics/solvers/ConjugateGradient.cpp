#include "bcassim/mechanics/solvers/ConjugateGradient.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "bcassim/Error.h"

namespace bcassim {

void JacobiPreconditioner::compute(const SparseMatrix& A) {
  invDiagonal_ = A.diagonal();
  for (Eigen::Index i = 0; i < invDiagonal_.size(); ++i) {
    const double d = invDiagonal_[i];
    if (!(d > 0.0) || !std::isfinite(d)) {
      throw NumericalError("Jacobi preconditioner: diagonal entry " + std::to_string(i) + " is " +
                           std::to_string(d) + ", expected a positive number");
    }
    invDiagonal_[i] = 1.0 / d;
  }
}

namespace {

// y = A x for the symmetric A of CG, stored with both triangles: column j of A is also its row
// j, so y_j is a dot product over column j. Eigen's column-major product scatters into y instead
// (a read-modify-write per entry), which made it the largest single cost of a PCG iteration.
void symmetricTimes(const SparseMatrix& A, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  if (!A.isCompressed()) {
    y.noalias() = A * x;
    return;
  }
  const Eigen::Index n = A.cols();
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  const double* xv = x.data();
  y.resize(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    double s0 = 0.0, s1 = 0.0;
    int k = outer[j];
    const int end = outer[j + 1];
    for (; k + 1 < end; k += 2) {
      s0 += value[k] * xv[inner[k]];
      s1 += value[k + 1] * xv[inner[k + 1]];
    }
    if (k < end) s0 += value[k] * xv[inner[k]];
    y[j] = s0 + s1;
  }
}

}  // namespace

SolveStatus preconditionedCg(const SparseMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             const Preconditioner& M, double relTol, int maxIter,
                             CgWorkspace& work) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n || b.size() != n) {
    throw std::invalid_argument("preconditionedCg: matrix and right-hand side sizes differ");
  }
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);
  auto& [r, z, p, Ap] = work;

  SolveStatus status;
  const double bNorm = b.norm();
  if (bNorm == 0.0) {  // the exact solution; also avoids dividing by |b| below
    x.setZero();
    return status;
  }
  const double threshold = relTol * bNorm;

  symmetricTimes(A, x, Ap);
  r = b - Ap;
  double rNorm = r.norm();
  bool restart = true;  // (re)start the search directions from the current residual
  double rz = 0.0;
  int k = 0;
  while (rNorm > threshold && k < maxIter) {
    if (restart) {
      M.apply(r, z);
      p = z;
      rz = r.dot(z);
      restart = false;
    }
    symmetricTimes(A, p, Ap);
    const double pAp = p.dot(Ap);
    if (!std::isfinite(pAp) || !std::isfinite(rz)) break;  // reported as not converged
    if (pAp <= 0.0) {
      throw NumericalError("conjugate gradients: matrix is not positive definite (p'Ap = " +
                           std::to_string(pAp) + " at iteration " + std::to_string(k + 1) + ")");
    }
    const double alpha = rz / pAp;
    x += alpha * p;
    r -= alpha * Ap;
    ++k;
    rNorm = r.norm();
    if (rNorm <= threshold) {
      // The recurrence drifts from b - A x in floating point: accept only the true residual,
      // and restart from it when they disagree.
      symmetricTimes(A, x, Ap);
      r = b - Ap;
      rNorm = r.norm();
      restart = true;
      continue;
    }
    M.apply(r, z);
    const double rzNew = r.dot(z);
    p = z + (rzNew / rz) * p;
    rz = rzNew;
  }
  if (!restart) {  // stopped on the recurrence (iteration limit): measure the true residual
    symmetricTimes(A, x, Ap);
    rNorm = (b - Ap).norm();
  }
  status.iterations = k;
  status.relativeResidual = rNorm / bNorm;
  status.converged = rNorm <= threshold;
  return status;
}

SolveStatus preconditionedCg(const SparseMatrix& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             const Preconditioner& M, double relTol, int maxIter) {
  CgWorkspace work;
  return preconditionedCg(A, b, x, M, relTol, maxIter, work);
}

}  // namespace bcassim
