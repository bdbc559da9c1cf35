#include "bcassim/assimilation/LargeDenseKernels.h"

#include <Eigen/Cholesky>
#include <stdexcept>

// Fortran BLAS/LAPACK (libblas.so.3 / liblapack.so.3: OpenBLAS through Debian's alternatives).
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
}

namespace bcassim {

void weightedGram(const Eigen::MatrixXd& D, const Eigen::VectorXd& w, Eigen::MatrixXd& P,
                  Eigen::Index largeFrom) {
  if (w.size() != D.cols()) throw std::invalid_argument("weightedGram: one weight per column");
  if ((w.array() < 0.0).any()) throw std::invalid_argument("weightedGram: negative weight");
  const Eigen::Index n = D.rows();
  if (n < largeFrom) {
    P.noalias() = D * w.asDiagonal() * D.transpose();
    return;
  }
  const Eigen::MatrixXd scaled = D * w.cwiseSqrt().asDiagonal();
  P.resize(n, n);
  const int nn = static_cast<int>(n), k = static_cast<int>(D.cols());
  const int lda = static_cast<int>(scaled.outerStride()), ldc = nn;
  const double one = 1.0, zero = 0.0;
  dsyrk_("L", "N", &nn, &k, &one, scaled.data(), &lda, &zero, P.data(), &ldc);
  P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
}

bool choleskyLower(const Eigen::MatrixXd& A, Eigen::MatrixXd& L, Eigen::Index largeFrom) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n) throw std::invalid_argument("choleskyLower: matrix is not square");
  if (n < largeFrom) {
    Eigen::LLT<Eigen::MatrixXd> llt(A);
    if (llt.info() != Eigen::Success) return false;
    L = llt.matrixL();
    return true;
  }
  L = A;
  const int nn = static_cast<int>(n), lda = nn;
  int info = 0;
  dpotrf_("L", &nn, L.data(), &lda, &info);
  if (info != 0) return false;
  L.triangularView<Eigen::StrictlyUpper>().setZero();
  return true;
}

}  // namespace bcassim
