// The contract every material fulfils: strain energy density, first Piola-Kirchhoff stress
// and its consistent tangent, all as functions of the deformation gradient F (thesis eq. 2.7-2.11).
#pragma once
#include <concepts>

#include "bcassim/Types.h"

namespace bcassim {

// energy(F): strain energy density Psi, J/m^3 (= Pa).
// pk1(F):    P = dPsi/dF, Pa.
// tangent(F): dP/dF as a 9x9 matrix, C(i, j) = d vec(P)_i / d vec(F)_j with vec() column-major
//            (index of entry (r, c) of a 3x3 matrix is r + 3c), Pa.
// pk1AndTangent(F, P, C): both at once, sharing the work (one SVD, one inverse) between them.
// admissible(F): whether F lies in the material's domain; outside it (e.g. det F <= 0 for laws
//            with ln J or J^(-1/3)) the outputs are non-finite. The hot loop does not check: the
//            FEM calls this where it needs to detect inverted elements.
// acceptsInverted: whether a tet with det F <= 0 is a state of the law rather than a failure.
//            Only the linear law's: quadratic in F and blind to volume, its equilibrium is one
//            linear system whatever it inverts (the small-strain law used far outside small
//            strain, not a failed solve). The others are undefined there (ln J) or have spurious
//            collapsed states (StVK, corotational): the FEM throws InvertedElementError for them.
// name():    short lower-case identifier used in scenes and reports.
template <class M>
concept HyperelasticMaterial = requires(const M& m, const Mat3& F, Mat3& P, Mat9& C) {
  { m.energy(F) } -> std::convertible_to<double>;
  { m.pk1(F) } -> std::convertible_to<Mat3>;
  { m.tangent(F) } -> std::convertible_to<Mat9>;
  { m.pk1AndTangent(F, P, C) } -> std::same_as<void>;
  { M::admissible(F) } -> std::convertible_to<bool>;
  { M::acceptsInverted } -> std::convertible_to<bool>;
  { M::name() } -> std::convertible_to<const char*>;
};

// Lame constants from Young's modulus E (Pa) and Poisson's ratio nu (-), nu in (-1, 0.5).
struct LameParameters {
  double lambda;  // Pa
  double mu;      // Pa (shear modulus)
  static LameParameters fromYoungPoisson(double E, double nu) {
    return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
  }
};

// Shear modulus mu and bulk modulus kappa (Pa) from E (Pa) and nu (-): the small-strain moduli
// that the nearly incompressible laws (Mooney-Rivlin, Ogden) are mapped to.
struct ShearBulkModuli {
  double mu;     // Pa
  double kappa;  // Pa
  static ShearBulkModuli fromYoungPoisson(double E, double nu) {
    return {E / (2.0 * (1.0 + nu)), E / (3.0 * (1.0 - 2.0 * nu))};
  }
};

}  // namespace bcassim
