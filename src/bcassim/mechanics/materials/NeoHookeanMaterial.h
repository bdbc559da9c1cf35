// Compressible neo-Hookean (Bonet & Wood 2008, eq. 6.28; thesis eq. 2.3 plus a volumetric term):
// Psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2, P = mu (F - F^-T) + lambda ln J F^-T.
#pragma once
#include <Eigen/LU>
#include <cmath>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/HyperelasticMaterial.h"
#include "bcassim/mechanics/materials/TangentTerms.h"

namespace bcassim {

// Only defined for J = det F > 0: elsewhere ln J makes every output non-finite (see admissible).
struct NeoHookeanMaterial {
  double lambda;  // first Lame constant, Pa
  double mu;      // shear modulus, Pa

  static NeoHookeanMaterial fromYoungPoisson(double E, double nu) {
    const auto l = LameParameters::fromYoungPoisson(E, nu);
    return {l.lambda, l.mu};
  }
  static const char* name() { return "neohookean"; }
  static bool admissible(const Mat3& F) { return F.determinant() > 0.0; }
  static constexpr bool acceptsInverted = false;

  double energy(const Mat3& F) const {
    const double lnJ = std::log(F.determinant());
    return 0.5 * mu * (F.squaredNorm() - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
  }

  Mat3 pk1(const Mat3& F) const {
    const double lnJ = std::log(F.determinant());
    const Mat3 H = F.inverse().transpose();
    return mu * F + (lambda * lnJ - mu) * H;
  }

  Mat9 tangent(const Mat3& F) const {
    Mat3 P;
    Mat9 C;
    pk1AndTangent(F, P, C);
    return C;
  }

  // dP = mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda (F^-T:dF) F^-T.
  void pk1AndTangent(const Mat3& F, Mat3& P, Mat9& C) const {
    const double lnJ = std::log(F.determinant());
    const Mat3 H = F.inverse().transpose();
    P = mu * F + (lambda * lnJ - mu) * H;
    C.setZero();
    C.diagonal().setConstant(mu);
    detail::addTransposedProduct(C, mu - lambda * lnJ, H);
    detail::addOuter(C, lambda, H);
  }
};

static_assert(HyperelasticMaterial<NeoHookeanMaterial>);

}  // namespace bcassim
