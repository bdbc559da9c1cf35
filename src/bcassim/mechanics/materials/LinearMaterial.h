// Isotropic linear elasticity (small strain; Bonet & Wood 2008, sec. 4.6; thesis sec. 2.1.3.1):
// eps = sym(F) - I, Psi = mu eps:eps + lambda/2 tr(eps)^2. Not frame indifferent.
#pragma once
#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/HyperelasticMaterial.h"

namespace bcassim {

struct LinearMaterial {
  double lambda;  // first Lame constant, Pa
  double mu;      // shear modulus, Pa

  static LinearMaterial fromYoungPoisson(double E, double nu) {
    const auto l = LameParameters::fromYoungPoisson(E, nu);
    return {l.lambda, l.mu};
  }
  static const char* name() { return "linear"; }
  // Defined for every F, inverted ones included.
  static bool admissible(const Mat3&) { return true; }
  // Inverted tets are states of this law, not failures (see HyperelasticMaterial.h).
  static constexpr bool acceptsInverted = true;

  double energy(const Mat3& F) const {
    const Mat3 eps = 0.5 * (F + F.transpose()) - Mat3::Identity();
    const double tr = eps.trace();
    return mu * eps.squaredNorm() + 0.5 * lambda * tr * tr;
  }

  Mat3 pk1(const Mat3& F) const {
    const double tr = F.trace() - 3.0;
    Mat3 P = mu * (F + F.transpose());
    P.diagonal().array() += lambda * tr - 2.0 * mu;
    return P;
  }

  // Constant: C(i + 3j, k + 3l) = mu (d_ik d_jl + d_il d_jk) + lambda d_ij d_kl.
  Mat9 tangent(const Mat3& = Mat3::Identity()) const {
    Mat9 C = Mat9::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        C(i + 3 * j, i + 3 * j) += mu;
        C(i + 3 * j, j + 3 * i) += mu;
        C(i + 3 * i, j + 3 * j) += lambda;
      }
    return C;
  }

  void pk1AndTangent(const Mat3& F, Mat3& P, Mat9& C) const {
    P = pk1(F);
    C = tangent(F);
  }
};

static_assert(HyperelasticMaterial<LinearMaterial>);

}  // namespace bcassim
