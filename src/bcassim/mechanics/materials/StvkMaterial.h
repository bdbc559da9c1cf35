// Saint Venant-Kirchhoff (thesis eq. 2.2; Bonet & Wood 2008, sec. 6.4.1), E = (F^T F - I)/2:
// Psi = lambda/2 tr(E)^2 + mu E:E, S = lambda tr(E) I + 2 mu E, P = F S.
#pragma once
#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/HyperelasticMaterial.h"
#include "bcassim/mechanics/materials/TangentTerms.h"

namespace bcassim {

struct StvkMaterial {
  double lambda;  // first Lame constant, Pa
  double mu;      // shear modulus, Pa

  static StvkMaterial fromYoungPoisson(double E, double nu) {
    const auto l = LameParameters::fromYoungPoisson(E, nu);
    return {l.lambda, l.mu};
  }
  static const char* name() { return "stvk"; }
  // Defined for every F; note the law softens and then collapses under strong compression.
  static bool admissible(const Mat3&) { return true; }
  static constexpr bool acceptsInverted = false;

  double energy(const Mat3& F) const {
    const Mat3 E = greenStrain(F);
    const double tr = E.trace();
    return 0.5 * lambda * tr * tr + mu * E.squaredNorm();
  }

  Mat3 pk1(const Mat3& F) const { return F * secondPiola(greenStrain(F)); }

  Mat9 tangent(const Mat3& F) const {
    Mat3 P;
    Mat9 C;
    pk1AndTangent(F, P, C);
    return C;
  }

  // dP = dF S + lambda (F:dF) F + mu (F F^T dF + F dF^T F).
  void pk1AndTangent(const Mat3& F, Mat3& P, Mat9& C) const {
    const Mat3 S = secondPiola(greenStrain(F));
    P.noalias() = F * S;
    C.setZero();
    detail::addRightProduct(C, 1.0, S);
    detail::addOuter(C, lambda, F);
    const Mat3 B = F * F.transpose();
    detail::addLeftProduct(C, mu, B);
    detail::addTransposedProduct(C, mu, F);
  }

 private:
  static Mat3 greenStrain(const Mat3& F) {
    Mat3 E = 0.5 * F.transpose() * F;
    E.diagonal().array() -= 0.5;
    return E;
  }
  Mat3 secondPiola(const Mat3& E) const {
    Mat3 S = 2.0 * mu * E;
    S.diagonal().array() += lambda * E.trace();
    return S;
  }
};

static_assert(HyperelasticMaterial<StvkMaterial>);

}  // namespace bcassim
