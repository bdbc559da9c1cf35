// Per-tet force and stiffness kernels. The generic one contracts the material tangent dP/dF with
// the shape gradients; closed forms for linear, StVK and Neo-Hookean skip the 9x9 tangent, which
// is what makes assembly fast enough for real time (see docs/benchmarks.md).
#pragma once
#include <cmath>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/Material.h"

namespace bcassim {

using ShapeGradients = Eigen::Matrix<double, 4, 3>;  // row a: grad N_a, 1/m
using ElementForces = Eigen::Matrix<double, 3, 4>;   // column a: force on node a, N

// Any material: f_a = V P grad N_a and K_{ai,bj} = V sum_kl C(i+3k, j+3l) gradN_a[k] gradN_b[l].
template <class M>
void elementForcesAndStiffness(const M& material, const Mat3& F, const ShapeGradients& G, double V,
                               ElementForces& f, Mat12& K) {
  Mat3 P;
  Mat9 C;
  if constexpr (requires { material.pk1AndTangent(F, P, C); }) {
    material.pk1AndTangent(F, P, C);
  } else {
    P = material.pk1(F);
    C = material.tangent(F);
  }
  f.noalias() = V * P * G.transpose();
  // CG(:, 3b+j) = sum_l C(:, j+3l) gradN_b[l], then K(3a+i, 3b+j) = sum_k gradN_a[k] CG(i+3k,
  // 3b+j).
  Eigen::Matrix<double, 9, 12> CG;
  for (int b = 0; b < 4; ++b)
    for (int j = 0; j < 3; ++j)
      CG.col(3 * b + j) =
          V * (C.col(j) * G(b, 0) + C.col(j + 3) * G(b, 1) + C.col(j + 6) * G(b, 2));
  for (int a = 0; a < 4; ++a)
    K.middleRows<3>(3 * a) =
        G(a, 0) * CG.topRows<3>() + G(a, 1) * CG.middleRows<3>(3) + G(a, 2) * CG.bottomRows<3>();
}

namespace detail {
// Fills K from blocks K_ab (b >= a) given by block(a, b), mirroring the symmetric part.
template <class BlockFn>
inline void fillSymmetricBlocks(Mat12& K, BlockFn&& block) {
  for (int a = 0; a < 4; ++a)
    for (int b = a; b < 4; ++b) {
      const Mat3 Kab = block(a, b);
      K.block<3, 3>(3 * a, 3 * b) = Kab;
      if (b != a) K.block<3, 3>(3 * b, 3 * a) = Kab.transpose();
    }
}
}  // namespace detail

// Linear: K_ab = V [mu (gNa.gNb) I + mu gNb gNa^T + lambda gNa gNb^T].
inline void elementForcesAndStiffness(const LinearMaterial& m, const Mat3& F,
                                      const ShapeGradients& G, double V, ElementForces& f,
                                      Mat12& K) {
  f.noalias() = V * m.pk1(F) * G.transpose();
  const Eigen::Matrix4d GG = G * G.transpose();
  detail::fillSymmetricBlocks(K, [&](int a, int b) {
    const Vec3 ga = G.row(a).transpose(), gb = G.row(b).transpose();
    Mat3 Kab = (m.mu * V) * gb * ga.transpose() + (m.lambda * V) * ga * gb.transpose();
    Kab.diagonal().array() += m.mu * V * GG(a, b);
    return Kab;
  });
}

// StVK: with g_a = F gradN_a, B = F F^T,
// K_ab = V [(gNa^T S gNb) I + lambda g_a g_b^T + mu (gNa.gNb) B + mu g_b g_a^T].
inline void elementForcesAndStiffness(const StvkMaterial& m, const Mat3& F, const ShapeGradients& G,
                                      double V, ElementForces& f, Mat12& K) {
  Mat3 E = 0.5 * F.transpose() * F;
  E.diagonal().array() -= 0.5;
  Mat3 S = 2.0 * m.mu * E;
  S.diagonal().array() += m.lambda * E.trace();
  f.noalias() = V * (F * S) * G.transpose();
  const Eigen::Matrix<double, 3, 4> g = F * G.transpose();
  const Eigen::Matrix4d GSG = G * S * G.transpose();
  const Eigen::Matrix4d GG = G * G.transpose();
  const Mat3 B = (m.mu * V) * F * F.transpose();
  detail::fillSymmetricBlocks(K, [&](int a, int b) {
    Mat3 Kab = (m.lambda * V) * g.col(a) * g.col(b).transpose() +
               (m.mu * V) * g.col(b) * g.col(a).transpose() + GG(a, b) * B;
    Kab.diagonal().array() += V * GSG(a, b);
    return Kab;
  });
}

// Neo-Hookean: P = mu F + (lambda ln J - mu) F^-T; with q_a = F^-T gradN_a,
// K_ab = V [mu (gNa.gNb) I + lambda q_a q_b^T - (lambda ln J - mu) q_b q_a^T].
inline void elementForcesAndStiffness(const NeoHookeanMaterial& m, const Mat3& F,
                                      const ShapeGradients& G, double V, ElementForces& f,
                                      Mat12& K) {
  const double J = F.determinant();
  const Mat3 FinvT = F.inverse().transpose();
  const double c = m.lambda * std::log(J) - m.mu;
  f.noalias() = V * (m.mu * F + c * FinvT) * G.transpose();
  const Eigen::Matrix<double, 3, 4> q = FinvT * G.transpose();
  const Eigen::Matrix4d GG = G * G.transpose();
  detail::fillSymmetricBlocks(K, [&](int a, int b) {
    Mat3 Kab = (m.lambda * V) * q.col(a) * q.col(b).transpose() -
               (c * V) * q.col(b) * q.col(a).transpose();
    Kab.diagonal().array() += m.mu * V * GG(a, b);
    return Kab;
  });
}

namespace detail {
// Rotation of the polar decomposition F = R S by Higham's scaled Newton iteration, which costs a
// few 3x3 inverses instead of an SVD. Returns false when F is too close to degenerate (or
// inverted) for the iteration to be trusted; the caller then uses the SVD-based material.
inline bool polarRotation(const Mat3& F, Mat3& R) {
  if (!(F.determinant() > 1e-3 * std::pow(F.squaredNorm() / 3.0, 1.5))) return false;
  R = F;
  for (int it = 0; it < 20; ++it) {
    const double det = R.determinant();
    const double zeta = it < 3 ? 1.0 / std::cbrt(std::abs(det)) : 1.0;
    const Mat3 next = 0.5 * (zeta * R + R.inverse().transpose() / zeta);
    const double change = (next - R).squaredNorm();
    R = next;
    if (change < 1e-28) return true;
  }
  return false;
}

inline Mat3 crossMatrix(const Vec3& v) {
  Mat3 m;
  m << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return m;
}
}  // namespace detail

// Corotational with its exact tangent: P = 2 mu (F - R) + lambda (tr S - 3) R, and with
// p_a = R gNa, M = (tr(S) I - S)^-1, c = lambda (tr S - 3) - 2 mu:
// K_ab = V [2 mu (gNa.gNb) I + lambda p_a p_b^T - c R [gNa]x M [gNb]x R^T]
// (the last term is the variation of R: R^T dR = [w]x with (tr(S) I - S) w = axial(2 skew(R^T
// dF))).
inline void elementForcesAndStiffness(const CorotationalMaterial& m, const Mat3& F,
                                      const ShapeGradients& G, double V, ElementForces& f,
                                      Mat12& K) {
  Mat3 R;
  if (!detail::polarRotation(F, R)) {
    elementForcesAndStiffness<CorotationalMaterial>(m, F, G, V, f, K);
    return;
  }
  Mat3 S = R.transpose() * F;
  S = 0.5 * (S + S.transpose()).eval();
  const double trS = S.trace();
  f.noalias() = V * (2.0 * m.mu * (F - R) + (m.lambda * (trS - 3.0)) * R) * G.transpose();
  Mat3 A = -S;
  A.diagonal().array() += trS;
  const Mat3 M = A.inverse();
  const double c = m.lambda * (trS - 3.0) - 2.0 * m.mu;
  const Eigen::Matrix<double, 3, 4> p = R * G.transpose();
  const Eigen::Matrix4d GG = G * G.transpose();
  Mat3 U[4], W[4];
  for (int a = 0; a < 4; ++a) {
    const Mat3 X = detail::crossMatrix(G.row(a).transpose());
    U[a] = (-c * V) * R * X;
    W[a] = M * X * R.transpose();
  }
  detail::fillSymmetricBlocks(K, [&](int a, int b) {
    Mat3 Kab = (m.lambda * V) * p.col(a) * p.col(b).transpose() + U[a] * W[b];
    Kab.diagonal().array() += 2.0 * m.mu * V * GG(a, b);
    return Kab;
  });
}

}  // namespace bcassim
