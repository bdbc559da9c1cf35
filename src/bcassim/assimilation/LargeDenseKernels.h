// The dense kernels that dominate a full-state UKF (a state of thousands of entries): weighted
// Gram matrix and Cholesky factor, on the system's BLAS/LAPACK. At run time that is OpenBLAS,
// whose kernels are chosen for the CPU (AVX-512 here), where Eigen in our x86-64-v2 build is
// limited to SSE; below kLargeDense rows the Eigen code is used (the call overhead would dominate).
#pragma once
#include <Eigen/Core>

namespace bcassim {

inline constexpr Eigen::Index kLargeDense = 200;

// P = D diag(w) D^T with w >= 0 (the weights of a sigma-point set); symmetric by construction.
void weightedGram(const Eigen::MatrixXd& D, const Eigen::VectorXd& w, Eigen::MatrixXd& P,
                  Eigen::Index largeFrom = kLargeDense);

// The lower Cholesky factor L of the symmetric A (L L^T = A, upper triangle zero); false if A
// is not (numerically) positive definite.
bool choleskyLower(const Eigen::MatrixXd& A, Eigen::MatrixXd& L,
                   Eigen::Index largeFrom = kLargeDense);

}  // namespace bcassim
