// The dense kernels that dominate a full-state UKF (a state of thousands of entries): weighted
// Gram matrix and Cholesky factor, on the system's BLAS/LAPACK. At run time that is OpenBLAS,
// whose kernels are chosen for the CPU (AVX-512 here), where Eigen in our x86-64-v2 build is
// limited to SSE; below kLargeDense rows the Eigen code is used (the call overhead would dominate).
#pragma once
#include <Eigen/Core>

namespace bcassim {

inline constexpr Eigen::Index kLargeDense = 200;

// P = D diag(w) D^T with w >= 0 (the weights of a sigma-point set); symmetric by construction.
void weightedGram(const Eigen::Ref<const Eigen::MatrixXd>& D,
                  const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::MatrixXd& P,
                  Eigen::Index largeFrom = kLargeDense);

// The lower triangle of the same, the strict upper triangle left unspecified (one pass less over
// an n x n matrix, for callers that mirror it once after summing several).
void weightedGramLower(const Eigen::Ref<const Eigen::MatrixXd>& D,
                       const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::MatrixXd& P,
                       Eigen::Index largeFrom = kLargeDense);

// C = A B (dgemm from kLargeDense rows of A).
void multiply(const Eigen::Ref<const Eigen::MatrixXd>& A,
              const Eigen::Ref<const Eigen::MatrixXd>& B, Eigen::MatrixXd& C,
              Eigen::Index largeFrom = kLargeDense);

// C = A B^T, B read in place (no transposed copy; dgemm from kLargeDense columns of B^T). Zero
// columns in common give C = 0.
void multiplyByTranspose(const Eigen::Ref<const Eigen::MatrixXd>& A,
                         const Eigen::Ref<const Eigen::MatrixXd>& B, Eigen::MatrixXd& C,
                         Eigen::Index largeFrom = kLargeDense);

// P -= G^T G for a symmetric P (n x n) and a short G (k x n): the Kalman update of a covariance.
void subtractGram(const Eigen::Ref<const Eigen::MatrixXd>& G, Eigen::MatrixXd& P,
                  Eigen::Index largeFrom = kLargeDense);

// The lower Cholesky factor L of the symmetric A (L L^T = A, upper triangle zero); false if A
// is not (numerically) positive definite.
bool choleskyLower(const Eigen::MatrixXd& A, Eigen::MatrixXd& L,
                   Eigen::Index largeFrom = kLargeDense);

}  // namespace bcassim
