// Corotational linear elasticity (thesis eq. 2.1; McAdams et al. 2011, Stomakhin et al. 2012),
// F = R S: Psi = mu |F - R|^2 + lambda/2 tr(R^T F - I)^2, P = 2 mu (F - R) + lambda tr(R^T F - I)
// R.
#pragma once
#include <cmath>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/HyperelasticMaterial.h"
#include "bcassim/mechanics/materials/IsotropicSpectral.h"

namespace bcassim {

// In the singular values s of F (det R = +1, so an inverted F has s_3 < 0):
// Psi = mu sum (s_i - 1)^2 + lambda/2 (sum s_i - 3)^2. The tangent includes the variation of R;
// it is unbounded where s_i + s_j -> 0 (R is not differentiable there, only reachable through
// inversion), so that denominator is clamped to kMinPairSum to keep the output finite.
struct CorotationalMaterial {
  double lambda;  // first Lame constant, Pa
  double mu;      // shear modulus, Pa

  static constexpr double kMinPairSum = 1e-6;

  static CorotationalMaterial fromYoungPoisson(double E, double nu) {
    const auto l = LameParameters::fromYoungPoisson(E, nu);
    return {l.lambda, l.mu};
  }
  static const char* name() { return "corotational"; }
  // Defined for every F, inverted ones included.
  static bool admissible(const Mat3&) { return true; }
  static constexpr bool acceptsInverted = false;

  double energy(const Mat3& F) const {
    const Vec3 s = detail::signedSingularValues(F);
    const double tr = s.sum() - 3.0;
    return mu * (s.array() - 1.0).square().sum() + 0.5 * lambda * tr * tr;
  }

  Mat3 pk1(const Mat3& F) const {
    const auto svd = detail::rotationVariantSvd(F);
    return detail::spectralStress(svd, stressInSingularValues(svd.sigma));
  }

  Mat9 tangent(const Mat3& F) const {
    Mat3 P;
    Mat9 C;
    pk1AndTangent(F, P, C);
    return C;
  }

  void pk1AndTangent(const Mat3& F, Mat3& P, Mat9& C) const {
    const auto svd = detail::rotationVariantSvd(F);
    const Vec3 dpsi = stressInSingularValues(svd.sigma);
    P = detail::spectralStress(svd, dpsi);
    Mat3 hess = Mat3::Constant(lambda);
    hess.diagonal().array() += 2.0 * mu;
    const Vec3 symm = Vec3::Constant(2.0 * mu);
    Vec3 skew;
    for (int p = 0; p < 3; ++p) {
      const int i = detail::kPairI[p], j = detail::kPairJ[p];
      double sum = svd.sigma(i) + svd.sigma(j);
      if (std::abs(sum) < kMinPairSum) sum = std::copysign(kMinPairSum, sum);
      skew(p) = (dpsi(i) + dpsi(j)) / sum;
    }
    C = detail::spectralTangent(svd, hess, symm, skew);
  }

 private:
  Vec3 stressInSingularValues(const Vec3& s) const {
    return (2.0 * mu * (s.array() - 1.0) + lambda * (s.sum() - 3.0)).matrix();
  }
};

static_assert(HyperelasticMaterial<CorotationalMaterial>);

}  // namespace bcassim
