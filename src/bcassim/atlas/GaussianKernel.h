// Gaussian interpolation kernel of LDDMM, thesis eqs. 4.1-4.4: K(x, y) = exp(-|x - y|^2 / sigma^2),
// the velocity v(x) = sum_j K(x, q_j) a_j and the Hamiltonian H = 1/2 a^T K(q, q) a.
#pragma once
#include <Eigen/Core>

namespace bcassim {

class GaussianKernel {
 public:
  // sigma: kernel width (m), > 0; throws InputError otherwise.
  explicit GaussianKernel(double sigma);

  double sigma() const { return sigma_; }
  double operator()(const Eigen::Vector3d& x, const Eigen::Vector3d& y) const;

  // Velocity at points: v_i = sum_j K(x_i, y_j) w_j.
  // x: #x by 3, y: #y by 3, w: #y by 3 (momenta at y). Returns #x by 3.
  Eigen::MatrixX3d convolve(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                            const Eigen::MatrixX3d& w) const;

  // Reverse-mode derivative of convolve: for L = sum_i eta_i . v_i, accumulates (+=)
  // dL/dx (#x by 3), dL/dy (#y by 3), dL/dw (#y by 3) into the non-null outputs, which must be
  // sized already. eta: #x by 3.
  void convolveVjp(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y, const Eigen::MatrixX3d& w,
                   const Eigen::MatrixX3d& eta, Eigen::MatrixX3d* gx, Eigen::MatrixX3d* gy,
                   Eigen::MatrixX3d* gw) const;

  // H(q, a) = 1/2 sum_ij K(q_i, q_j) a_i . a_j. q, a: #q by 3.
  double hamiltonian(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a) const;

  // dH/dq, #q by 3: the momentum equation of eq. 4.4 is a' = -dH/dq.
  Eigen::MatrixX3d hamiltonianGradient(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a) const;

  // Reverse-mode derivative of hamiltonianGradient: for L = sum_i xi_i . (dH/dq)_i, accumulates
  // (+=) dL/dq and dL/da (#q by 3 each) into the non-null outputs.
  void hamiltonianGradientVjp(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a,
                              const Eigen::MatrixX3d& xi, Eigen::MatrixX3d* gq,
                              Eigen::MatrixX3d* ga) const;

 private:
  double sigma_;
  double invSigma2_;
};

}  // namespace bcassim
