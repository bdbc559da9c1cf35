#include "bcassim/assimilation/LargeDenseKernels.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "bcassim/Blas.h"

namespace bcassim {

void weightedGramLower(const Eigen::Ref<const Eigen::MatrixXd>& D,
                       const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::MatrixXd& P,
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
  if (k > 0) {
    dsyrk_("L", "N", &nn, &k, &one, scaled.data(), &lda, &zero, P.data(), &ldc);
  } else {
    P.triangularView<Eigen::Lower>().setZero();
  }
}

void weightedGram(const Eigen::Ref<const Eigen::MatrixXd>& D,
                  const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::MatrixXd& P,
                  Eigen::Index largeFrom) {
  weightedGramLower(D, w, P, largeFrom);
  if (D.rows() >= largeFrom) P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
}

namespace {
// C = A B (or A B^T) by BLAS: C is resized to A's rows by B's columns (or rows).
void gemm(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B,
          bool transposeB, Eigen::MatrixXd& C) {
  const int m = static_cast<int>(A.rows());
  const int n = static_cast<int>(transposeB ? B.rows() : B.cols());
  const int k = static_cast<int>(A.cols());
  C.resize(m, n);
  const int lda = static_cast<int>(A.outerStride()), ldb = static_cast<int>(B.outerStride());
  const double one = 1.0, zero = 0.0;
  dgemm_("N", transposeB ? "T" : "N", &m, &n, &k, &one, A.data(), &lda, B.data(), &ldb, &zero,
         C.data(), &m);
}
}  // namespace

void multiply(const Eigen::Ref<const Eigen::MatrixXd>& A,
              const Eigen::Ref<const Eigen::MatrixXd>& B, Eigen::MatrixXd& C,
              Eigen::Index largeFrom) {
  if (A.cols() != B.rows()) throw std::invalid_argument("multiply: sizes disagree");
  if (A.rows() < largeFrom || A.cols() == 0 || B.cols() == 0) {
    C.noalias() = A * B;
    return;
  }
  gemm(A, B, false, C);
}

void multiplyByTranspose(const Eigen::Ref<const Eigen::MatrixXd>& A,
                         const Eigen::Ref<const Eigen::MatrixXd>& B, Eigen::MatrixXd& C,
                         Eigen::Index largeFrom) {
  if (A.cols() != B.cols()) throw std::invalid_argument("multiplyByTranspose: sizes disagree");
  if (B.rows() < largeFrom || A.rows() == 0 || A.cols() == 0) {
    C.noalias() = A * B.transpose();
    return;
  }
  gemm(A, B, true, C);
}

void subtractGram(const Eigen::Ref<const Eigen::MatrixXd>& G, Eigen::MatrixXd& P,
                  Eigen::Index largeFrom) {
  const Eigen::Index n = P.rows();
  if (G.cols() != n || P.cols() != n) throw std::invalid_argument("subtractGram: sizes disagree");
  if (n < largeFrom || G.rows() == 0) {
    P.noalias() -= G.transpose() * G;
    return;
  }
  const int nn = static_cast<int>(n), k = static_cast<int>(G.rows());
  const int ldg = static_cast<int>(G.outerStride()), ldp = static_cast<int>(P.outerStride());
  const double minusOne = -1.0, one = 1.0;
  dsyrk_("L", "T", &nn, &k, &minusOne, G.data(), &ldg, &one, P.data(), &ldp);
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
