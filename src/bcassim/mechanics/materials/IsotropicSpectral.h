// Stress and tangent of an isotropic energy written in the singular values of F = U diag(s) V^T
// (Irving, Teran & Fedkiw 2004; Stomakhin et al. 2012, "Energetically consistent invertible
// elasticity"). Shared by the corotational and Ogden materials.
#pragma once
#include <Eigen/SVD>
#include <cmath>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/TangentTerms.h"

namespace bcassim::detail {

// F = U diag(sigma) V^T with U and V proper rotations: the sign of det F is carried by sigma(2),
// the smallest in magnitude, so an inverted F still has a rotation as its polar factor.
struct RotationVariantSvd {
  Mat3 U;
  Vec3 sigma;
  Mat3 V;
};

inline RotationVariantSvd rotationVariantSvd(const Mat3& F) {
  // Jacobi SVD works on F itself rather than on F^T F, so small stretches keep full accuracy.
  const Eigen::JacobiSVD<Mat3, Eigen::NoQRPreconditioner> svd(
      F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationVariantSvd r{svd.matrixU(), svd.singularValues(), svd.matrixV()};
  if (r.U.determinant() < 0) {
    r.U.col(2) = -r.U.col(2);
    r.sigma(2) = -r.sigma(2);
  }
  if (r.V.determinant() < 0) {
    r.V.col(2) = -r.V.col(2);
    r.sigma(2) = -r.sigma(2);
  }
  return r;
}

// Signed singular values only (for energies), same convention as rotationVariantSvd.
inline Vec3 signedSingularValues(const Mat3& F) {
  Vec3 s = Eigen::JacobiSVD<Mat3, Eigen::NoQRPreconditioner>(F).singularValues();
  if (F.determinant() < 0) s(2) = -s(2);
  return s;
}

// The index pairs (i, j), i < j, in the order used by the per-pair coefficient arrays below.
inline constexpr int kPairI[3] = {0, 0, 1};
inline constexpr int kPairJ[3] = {1, 2, 2};

// (x^p - y^p) / (x - y) for x, y > 0, exact as x -> y (where it tends to p x^(p-1)): written with
// expm1/log1p so the subtraction of nearly equal powers never cancels.
inline double powerDividedDifference(double x, double y, double p) {
  if (x == y) return p * std::pow(x, p - 1.0);
  const double t = (x - y) / y;
  return std::pow(y, p - 1.0) * std::expm1(p * std::log1p(t)) / t;
}

// P = U diag(dpsi) V^T, with dpsi the gradient of the energy in the singular values.
inline Mat3 spectralStress(const RotationVariantSvd& svd, const Vec3& dpsi) {
  return svd.U * dpsi.asDiagonal() * svd.V.transpose();
}

// dP/dF from, in the singular-value frame: hess = d2psi/dsigma2 (3x3, symmetric), and per pair p
// of (i, j) = (kPairI[p], kPairJ[p]): symm(p) = (dpsi_i - dpsi_j) / (sigma_i - sigma_j), which
// scales the symmetric off-diagonal mode u_i v_j^T + u_j v_i^T, and skew(p) = (dpsi_i + dpsi_j) /
// (sigma_i + sigma_j), which scales the antisymmetric one u_i v_j^T - u_j v_i^T. The caller
// evaluates symm in a form that stays exact for equal sigmas. The result is symmetric.
inline Mat9 spectralTangent(const RotationVariantSvd& svd, const Mat3& hess, const Vec3& symm,
                            const Vec3& skew) {
  const Mat3& U = svd.U;
  const Mat3& V = svd.V;
  Eigen::Matrix<double, 9, 3> D;  // columns vec(u_m v_m^T): the diagonal (stretch) modes
  for (int m = 0; m < 3; ++m) {
    const Mat3 uv = U.col(m) * V.col(m).transpose();
    D.col(m) = vec(uv);
  }
  Mat9 C;
  C.noalias() = D * (hess * D.transpose());
  for (int p = 0; p < 3; ++p) {
    const int i = kPairI[p], j = kPairJ[p];
    const Mat3 a = U.col(i) * V.col(j).transpose();
    const Mat3 b = U.col(j) * V.col(i).transpose();
    // Both modes have squared norm 2, hence the halves.
    const Vec9 s = vec(a) + vec(b);
    const Vec9 w = vec(a) - vec(b);
    C.noalias() += (0.5 * symm(p) * s) * s.transpose();
    C.noalias() += (0.5 * skew(p) * w) * w.transpose();
  }
  return C;
}

}  // namespace bcassim::detail
