#include "bcassim/mechanics/solvers/ConjugateGradient.h"

#include <cmath>
#include <cstring>
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
// Whether the columns come in triples (the 3 dofs of a node) with identical row patterns, as
// in every matrix assembled on our node-block pattern; then one gather of x serves 3 columns.
bool hasNodeBlockColumns(const SparseMatrix& A) {
  if (!A.isCompressed() || A.cols() % 3 != 0) return false;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (Eigen::Index j = 0; j < A.cols(); j += 3) {
    const int length = outer[j + 1] - outer[j];
    if (outer[j + 2] - outer[j + 1] != length || outer[j + 3] - outer[j + 2] != length)
      return false;
    const auto bytes = static_cast<std::size_t>(length) * sizeof(int);
    if (std::memcmp(inner + outer[j], inner + outer[j + 1], bytes) != 0 ||
        std::memcmp(inner + outer[j], inner + outer[j + 2], bytes) != 0)
      return false;
  }
  return true;
}

void symmetricTimes(const SparseMatrix& A, const Eigen::VectorXd& x, Eigen::VectorXd& y,
                    bool nodeBlocks) {
  if (!A.isCompressed()) {
    y.noalias() = A * x;
    return;
  }
  if (nodeBlocks) {
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* value = A.valuePtr();
    const double* xv = x.data();
    y.resize(A.cols());
    for (Eigen::Index j = 0; j < A.cols(); j += 3) {
      const int k0 = outer[j], length = outer[j + 1] - k0;
      const double* v0 = value + k0;
      const double* v1 = value + outer[j + 1];
      const double* v2 = value + outer[j + 2];
      const int* rows = inner + k0;
      double s0 = 0.0, s1 = 0.0, s2 = 0.0;
      for (int i = 0; i < length; ++i) {
        const double xi = xv[rows[i]];
        s0 += v0[i] * xi;
        s1 += v1[i] * xi;
        s2 += v2[i] * xi;
      }
      y[j] = s0;
      y[j + 1] = s1;
      y[j + 2] = s2;
    }
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
  const bool nodeBlocks = hasNodeBlockColumns(A);

  symmetricTimes(A, x, Ap, nodeBlocks);
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
    symmetricTimes(A, p, Ap, nodeBlocks);
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
      symmetricTimes(A, x, Ap, nodeBlocks);
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
    symmetricTimes(A, x, Ap, nodeBlocks);
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
