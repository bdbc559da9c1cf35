// Stress and tangent of an isotropic energy written in the singular values of F = U diag(s) V^T
// (Irving, Teran & Fedkiw 2004; Stomakhin et al. 2012, "Energetically consistent invertible
// elasticity"). Shared by the corotational and Ogden materials.
#pragma once
#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/TangentTerms.h"

namespace bcassim::detail {

// F = U diag(sigma) V^T with U and V proper rotations: the sign of det F is carried by sigma(2),
// the smallest in magnitude, so an inverted F still has a rotation as its polar factor.
// sigma(0) >= sigma(1) >= |sigma(2)|.
struct RotationVariantSvd {
  Mat3 U;
  Vec3 sigma;
  Mat3 V;
};

// A unit vector orthogonal to the unit vector u.
inline Vec3 anyOrthogonal(const Vec3& u) {
  Eigen::Index k;
  u.cwiseAbs().minCoeff(&k);
  return u.cross(Vec3::Unit(k)).normalized();
}

// One-sided (Hestenes) Jacobi: plane rotations on the right orthogonalise the columns of B = F V,
// which is Jacobi on F^T F without ever forming it, so small singular values and their vectors
// keep full relative accuracy (Demmel & Veselic 1992). U then comes from Gram-Schmidt on B, closed
// with u3 = u1 x u2 so U is a rotation and sigma(2) = u3 . b3 takes the sign of det F (the QR
// step of McAdams et al. 2011). Rank-deficient F (even F = 0) gets an arbitrary valid basis.
inline RotationVariantSvd rotationVariantSvd(const Mat3& F) {
  constexpr double kEps = 2.2204460492503131e-16;
  constexpr double kTiny = 1e-280;
  RotationVariantSvd r;
  Mat3 B = F;
  Mat3& V = r.V;
  V.setIdentity();
  for (int sweep = 0; sweep < 20; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const double a = B.col(p).squaredNorm(), b = B.col(q).squaredNorm();
        const double g = B.col(p).dot(B.col(q));
        if (g * g <= kEps * kEps * a * b) continue;
        rotated = true;
        // Diagonalises [[a, g], [g, b]]: Golub & Van Loan, Matrix Computations, alg. 8.5.1.
        const double zeta = (b - a) / (2.0 * g);
        const double t =
            std::abs(zeta) > 1e150
                ? 0.5 / zeta
                : std::copysign(1.0, zeta) / (std::abs(zeta) + std::sqrt(1.0 + zeta * zeta));
        const double c = 1.0 / std::sqrt(1.0 + t * t);
        const double s = t * c;
        const Vec3 bp = B.col(p), vp = V.col(p);
        B.col(p) = c * bp - s * B.col(q);
        B.col(q) = s * bp + c * B.col(q);
        V.col(p) = c * vp - s * V.col(q);
        V.col(q) = s * vp + c * V.col(q);
      }
    if (!rotated) break;
  }
  Vec3 n2(B.col(0).squaredNorm(), B.col(1).squaredNorm(), B.col(2).squaredNorm());
  auto order = [&](int i, int j) {
    if (n2(i) < n2(j)) {
      std::swap(n2(i), n2(j));
      B.col(i).swap(B.col(j));
      V.col(i).swap(V.col(j));
    }
  };
  order(0, 1);
  order(0, 2);
  order(1, 2);
  if (V.determinant() < 0.0) {
    V.col(2) = -V.col(2);
    B.col(2) = -B.col(2);
  }
  const double s1 = std::sqrt(n2(0));
  const Vec3 u1 = s1 > kTiny ? Vec3(B.col(0) / s1) : Vec3::UnitX();
  Vec3 b2 = B.col(1) - u1.dot(B.col(1)) * u1;
  const double s2 = b2.norm();
  Vec3 u2 = anyOrthogonal(u1);
  if (s2 > kTiny) {
    b2 /= s2;
    b2 -= u1.dot(b2) * u1;  // a second pass restores orthogonality lost to cancellation
    u2 = b2.normalized();
  }
  const Vec3 u3 = u1.cross(u2);
  r.U << u1, u2, u3;
  r.sigma << s1, s2, u3.dot(B.col(2));
  return r;
}

// Signed singular values only (for energies), same convention as rotationVariantSvd.
inline Vec3 signedSingularValues(const Mat3& F) { return rotationVariantSvd(F).sigma; }

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
  // C = W M W^T with W = [stretch modes | symmetric modes | antisymmetric modes] (all columns
  // vec(u_a v_b^T) or sums of two) and M block diagonal; one fixed-size product, no scatter.
  // K(:, a + 3b) = vec(u_a v_b^T), whose entry (i, j) is U(i, a) V(j, b).
  Mat9 K;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a)
      for (int j = 0; j < 3; ++j) K.block<3, 1>(3 * j, a + 3 * b) = svd.V(j, b) * svd.U.col(a);
  Mat9 W;
  for (int m = 0; m < 3; ++m) W.col(m) = K.col(m + 3 * m);
  for (int p = 0; p < 3; ++p) {
    const int i = kPairI[p], j = kPairJ[p];
    W.col(3 + p) = K.col(i + 3 * j) + K.col(j + 3 * i);
    W.col(6 + p) = K.col(i + 3 * j) - K.col(j + 3 * i);
  }
  Mat9 WM;
  WM.leftCols<3>().noalias() = W.leftCols<3>() * hess;
  // Both off-diagonal modes have squared norm 2, hence the halves.
  for (int p = 0; p < 3; ++p) {
    WM.col(3 + p) = (0.5 * symm(p)) * W.col(3 + p);
    WM.col(6 + p) = (0.5 * skew(p)) * W.col(6 + p);
  }
  Mat9 C;
  C.noalias() = WM * W.transpose();
  return C;
}

}  // namespace bcassim::detail
