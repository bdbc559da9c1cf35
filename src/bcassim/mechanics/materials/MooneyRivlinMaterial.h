// Compressible Mooney-Rivlin with isochoric invariants (thesis eq. 2.4 with N = 1; Bonet & Wood
// 2008, sec. 6.6): Psi = c10 (J^-2/3 I1 - 3) + c01 (J^-4/3 I2 - 3) + kappa/2 (J - 1)^2.
#pragma once
#include <Eigen/LU>
#include <cmath>

#include "bcassim/Types.h"
#include "bcassim/mechanics/materials/HyperelasticMaterial.h"
#include "bcassim/mechanics/materials/TangentTerms.h"

namespace bcassim {

// Small-strain moduli: shear mu = 2 (c10 + c01), bulk kappa (the isochoric part has no volumetric
// stiffness). Only defined for J = det F > 0: elsewhere J^(-2/3) makes the outputs non-finite.
struct MooneyRivlinMaterial {
  double c10;    // Pa
  double c01;    // Pa
  double kappa;  // bulk modulus, Pa

  // Thesis sec. 2.1.5 beam comparison: c10 = 0.2112 MPa, c01 = 0.0617 MPa.
  static constexpr double kThesisC10 = 0.2112e6;
  static constexpr double kThesisC01 = 0.0617e6;

  // Matches the small-strain shear and bulk moduli of (E, nu); c01/c10 defaults to the thesis'.
  static MooneyRivlinMaterial fromYoungPoisson(double E, double nu,
                                               double c01OverC10 = kThesisC01 / kThesisC10) {
    const auto m = ShearBulkModuli::fromYoungPoisson(E, nu);
    const double c10 = 0.5 * m.mu / (1.0 + c01OverC10);
    return {c10, c01OverC10 * c10, m.kappa};
  }
  // The thesis parameters, kappa chosen so the small-strain Poisson ratio is nu.
  static MooneyRivlinMaterial thesis(double nu = 0.49) {
    const double mu = 2.0 * (kThesisC10 + kThesisC01);
    return {kThesisC10, kThesisC01, 2.0 * mu * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))};
  }
  static const char* name() { return "mooneyrivlin"; }
  static bool admissible(const Mat3& F) { return F.determinant() > 0.0; }
  static constexpr bool acceptsInverted = false;

  double energy(const Mat3& F) const {
    const double J = F.determinant();
    const Mat3 Cg = F.transpose() * F;
    const double I1 = Cg.trace();
    const double I2 = 0.5 * (I1 * I1 - Cg.squaredNorm());
    const double j23 = std::pow(J, -2.0 / 3.0);
    return c10 * (j23 * I1 - 3.0) + c01 * (j23 * j23 * I2 - 3.0) +
           0.5 * kappa * (J - 1.0) * (J - 1.0);
  }

  Mat3 pk1(const Mat3& F) const {
    const Kinematics k(F);
    return stress(F, k);
  }

  Mat9 tangent(const Mat3& F) const {
    Mat3 P;
    Mat9 C;
    pk1AndTangent(F, P, C);
    return C;
  }

  // The stress below differentiated term by term, with H = F^-T, G = I1 F - F C (dI2/dF = 2G):
  // dH = -H dF^T H and the F dF^T F part of dG are the addTransposedProduct terms.
  void pk1AndTangent(const Mat3& F, Mat3& P, Mat9& C) const {
    const Kinematics k(F);
    P = stress(F, k);
    const double a = c10 * k.j23;
    const double b = c01 * k.j43;
    C.setZero();
    C.diagonal().setConstant(2.0 * a + 2.0 * b * k.I1);
    detail::addSymOuter(C, -4.0 / 3.0 * a, F, k.H);
    detail::addSymOuter(C, -8.0 / 3.0 * b, k.G, k.H);
    detail::addOuter(
        C, 4.0 / 9.0 * a * k.I1 + 16.0 / 9.0 * b * k.I2 + kappa * (2.0 * k.J - 1.0) * k.J, k.H);
    detail::addTransposedProduct(
        C, 2.0 / 3.0 * a * k.I1 + 4.0 / 3.0 * b * k.I2 - kappa * k.J * (k.J - 1.0), k.H);
    detail::addOuter(C, 4.0 * b, F);
    detail::addRightProduct(C, -2.0 * b, k.Cg);
    detail::addLeftProduct(C, -2.0 * b, F * F.transpose());
    detail::addTransposedProduct(C, -2.0 * b, F);
  }

 private:
  struct Kinematics {
    explicit Kinematics(const Mat3& F)
        : J(F.determinant()),
          H(F.inverse().transpose()),
          Cg(F.transpose() * F),
          I1(Cg.trace()),
          I2(0.5 * (I1 * I1 - Cg.squaredNorm())),
          G(I1 * F - F * Cg),
          j23(std::pow(J, -2.0 / 3.0)),
          j43(j23 * j23) {}
    double J;
    Mat3 H;
    Mat3 Cg;
    double I1;
    double I2;
    Mat3 G;
    double j23;
    double j43;
  };

  // P = c10 J^-2/3 (2F - 2/3 I1 H) + c01 J^-4/3 (2G - 4/3 I2 H) + kappa (J - 1) J H.
  Mat3 stress(const Mat3& F, const Kinematics& k) const {
    const double a = c10 * k.j23;
    const double b = c01 * k.j43;
    return (2.0 * a) * F + (2.0 * b) * k.G +
           (kappa * (k.J - 1.0) * k.J - 2.0 / 3.0 * a * k.I1 - 4.0 / 3.0 * b * k.I2) * k.H;
  }
};

static_assert(HyperelasticMaterial<MooneyRivlinMaterial>);

}  // namespace bcassim
