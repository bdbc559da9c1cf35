// Building blocks of the 9x9 tangents dP/dF (vec column-major: entry (r, c) sits at r + 3c) shared
// by the materials whose stress is written with F, F^-T and invariants (Bonet & Wood 2008, ch. 6).
#pragma once
#include <Eigen/Core>

#include "bcassim/Types.h"

namespace bcassim::detail {

using Vec9 = Eigen::Matrix<double, 9, 1>;

inline Eigen::Map<const Vec9> vec(const Mat3& A) { return Eigen::Map<const Vec9>(A.data()); }

// C += a vec(A) vec(A)^T.
inline void addOuter(Mat9& C, double a, const Mat3& A) {
  C.noalias() += (a * vec(A)) * vec(A).transpose();
}

// C += a (vec(A) vec(B)^T + vec(B) vec(A)^T).
inline void addSymOuter(Mat9& C, double a, const Mat3& A, const Mat3& B) {
  const Vec9 aA = a * vec(A);
  C.noalias() += aA * vec(B).transpose();
  C.noalias() += vec(B) * aA.transpose();
}

// C += a d(H dF^T H)/dF, i.e. C(i + 3j, k + 3l) += a H(i, l) H(k, j). With H = F^-T this is the
// derivative of F^-T up to sign: d(F^-T) = -F^-T dF^T F^-T.
inline void addTransposedProduct(Mat9& C, double a, const Mat3& H) {
  for (int l = 0; l < 3; ++l) {
    const Vec3 aHl = a * H.col(l);
    for (int j = 0; j < 3; ++j) C.block<3, 3>(3 * j, 3 * l).noalias() += aHl * H.col(j).transpose();
  }
}

// C += a d(B dF)/dF, i.e. C(i + 3j, k + 3l) += a B(i, k) delta(j, l).
inline void addLeftProduct(Mat9& C, double a, const Mat3& B) {
  for (int j = 0; j < 3; ++j) C.block<3, 3>(3 * j, 3 * j) += a * B;
}

// C += a d(dF S)/dF, i.e. C(i + 3j, k + 3l) += a delta(i, k) S(l, j).
inline void addRightProduct(Mat9& C, double a, const Mat3& S) {
  for (int j = 0; j < 3; ++j)
    for (int l = 0; l < 3; ++l) {
      const double s = a * S(l, j);
      for (int i = 0; i < 3; ++i) C(i + 3 * j, i + 3 * l) += s;
    }
}

}  // namespace bcassim::detail
