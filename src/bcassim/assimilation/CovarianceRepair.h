// Cholesky factors of covariances that may have lost positive definiteness to round-off (a
// collapsed direction, an indefinite update): repaired by symmetrising and adding a growing jitter.
#pragma once
#include <Eigen/Core>

namespace bcassim {

// Repairs made during one filter step, reported rather than printed.
struct RepairLog {
  int repairs = 0;             // factorisations that needed jitter
  double largestJitter = 0.0;  // largest multiple of the identity added
};

// Lower-triangular C with C C^T = P. If the Cholesky factorisation of P fails, P is symmetrised and
// jitter * I is added, jitter starting at 1e-10 times the mean diagonal and growing x10 until it
// factorises; the repair is recorded in `log`. Throws NumericalError if P is not finite or no
// jitter up to 1e10 times the mean diagonal helps.
Eigen::MatrixXd choleskyWithRepair(const Eigen::MatrixXd& P, RepairLog& log);

}  // namespace bcassim
