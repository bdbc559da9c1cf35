// One-term compressible Ogden (thesis eq. 2.5, liver ground truth of sec. 5; Ogden 1972):
// Psi = 2 mu / alpha^2 (l1^a + l2^a + l3^a - 3) + kappa/2 (J - 1)^2, li = J^-1/3 x stretch i.
#pragma once
#include <cmath>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/HyperelasticMaterial.h"
#include "bcassim/mechanics/materials/IsotropicSpectral.h"

namespace bcassim {

// Small-strain moduli: shear mu, bulk kappa. The principal stretches are the singular values of F
// (the square roots of the eigenvalues of C = F^T F, computed without squaring F so that small
// stretches stay accurate). The tangent is exact for coincident stretches: the divided
// differences it needs are evaluated in a form that tends to the derivative without cancelling.
// Only defined for J = det F > 0: elsewhere the fractional powers make the outputs non-finite.
// FEBio's Ogden writes the term as c/m^2 (...): a FEBio c is mu = c/2 here, m is alpha.
struct OgdenMaterial {
  double mu;     // shear modulus, Pa
  double alpha;  // exponent, -
  double kappa;  // bulk modulus, Pa

  // Human liver parameters of the thesis' ground truth (sec. 5, its ref. [127]), read as mu.
  static constexpr double kLiverMu = 16.47e3;
  static constexpr double kLiverAlpha = 0.88;
  static constexpr double kLiverNu = 0.49;

  // Matches the small-strain shear and bulk moduli of (E, nu).
  static OgdenMaterial fromYoungPoisson(double E, double nu, double alpha = kLiverAlpha) {
    const auto m = ShearBulkModuli::fromYoungPoisson(E, nu);
    return {m.mu, alpha, m.kappa};
  }
  // The thesis liver, kappa chosen so the small-strain Poisson ratio is nu.
  static OgdenMaterial liver(double nu = kLiverNu) {
    return {kLiverMu, kLiverAlpha, 2.0 * kLiverMu * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))};
  }
  static const char* name() { return "ogden"; }
  static bool admissible(const Mat3& F) { return F.determinant() > 0.0; }
  static constexpr bool acceptsInverted = false;

  double energy(const Mat3& F) const {
    const Vec3 s = detail::signedSingularValues(F);
    const double J = s.prod();
    const double sumBar = (s.array() * std::cbrt(1.0 / J)).pow(alpha).sum();
    return 2.0 * mu / (alpha * alpha) * (sumBar - 3.0) + 0.5 * kappa * (J - 1.0) * (J - 1.0);
  }

  Mat3 pk1(const Mat3& F) const {
    const auto svd = detail::rotationVariantSvd(F);
    const Spectral q(*this, svd.sigma);
    return detail::spectralStress(svd, q.dpsi);
  }

  Mat9 tangent(const Mat3& F) const {
    Mat3 P;
    Mat9 C;
    pk1AndTangent(F, P, C);
    return C;
  }

  // In the stretches s: with beta = J^(-alpha/3), S = sum s_i^alpha and the Kirchhoff principal
  // stresses tau_i = s_i dpsi_i = 2 mu / alpha beta (s_i^alpha - S/3) + kappa (J - 1) J,
  // s_i s_j d2psi_ij = 2 mu beta (d_ij s_i^alpha - (s_i^alpha + s_j^alpha)/3 + S/9)
  //                    + kappa (2J - 1) J - d_ij tau_i.
  void pk1AndTangent(const Mat3& F, Mat3& P, Mat9& C) const {
    const auto svd = detail::rotationVariantSvd(F);
    const Vec3& s = svd.sigma;
    const Spectral q(*this, s);
    P = detail::spectralStress(svd, q.dpsi);

    const double vol2 = kappa * (2.0 * q.J - 1.0) * q.J;
    Mat3 hess;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double v = 2.0 * mu * q.beta * (q.S / 9.0 - (q.pw(i) + q.pw(j)) / 3.0) + vol2;
        if (i == j) v += 2.0 * mu * q.beta * q.pw(i) - q.tau(i);
        hess(i, j) = v / (s(i) * s(j));
      }

    // dpsi_i = c s_i^(alpha-1) + K / s_i with c = 2 mu beta / alpha, K = kappa (J-1) J - c S/3.
    const double c = 2.0 * mu * q.beta / alpha;
    const double K = kappa * (q.J - 1.0) * q.J - c * q.S / 3.0;
    Vec3 symm, skew;
    for (int p = 0; p < 3; ++p) {
      const int i = detail::kPairI[p], j = detail::kPairJ[p];
      symm(p) = c * detail::powerDividedDifference(s(i), s(j), alpha - 1.0) - K / (s(i) * s(j));
      skew(p) = (q.dpsi(i) + q.dpsi(j)) / (s(i) + s(j));
    }
    C = detail::spectralTangent(svd, hess, symm, skew);
  }

 private:
  // Quantities shared by stress and tangent, from the signed stretches s.
  struct Spectral {
    Spectral(const OgdenMaterial& m, const Vec3& s)
        : J(s.prod()), beta(std::pow(J, -m.alpha / 3.0)), pw(s.array().pow(m.alpha)), S(pw.sum()) {
      tau =
          (2.0 * m.mu / m.alpha * beta * (pw.array() - S / 3.0) + m.kappa * (J - 1.0) * J).matrix();
      dpsi = tau.cwiseQuotient(s);
    }
    double J;
    double beta;
    Vec3 pw;  // s_i^alpha
    double S;
    Vec3 tau;
    Vec3 dpsi;
  };
};

static_assert(HyperelasticMaterial<OgdenMaterial>);

}  // namespace bcassim
