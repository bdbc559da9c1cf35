// Incompressible hyperelastic laws under uniaxial tension in closed form (thesis eq. 4.9's
// tau(lambda, Psi, C_mat)): the nominal stress of a stretch for Neo-Hookean, Mooney-Rivlin and
// one-term Ogden, written as mechanics/materials writes them, so that a fit sets a material.
#pragma once
#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

namespace bcassim {

// Parameters, in this order (Pa unless said):
//   NeoHookean    mu (shear modulus): Psi = mu/2 (I1 - 3),       sigma = mu (l^2 - 1/l)
//   MooneyRivlin  c10, c01: Psi = c10 (I1 - 3) + c01 (I2 - 3),   sigma = 2 (l^2 - 1/l)(c10 + c01/l)
//   Ogden         mu, alpha (-): Psi = 2 mu/alpha^2 sum(li^alpha - 1),
//                 sigma = 2 mu/alpha (l^alpha - l^(-alpha/2))
// sigma is the Cauchy stress; the nominal (first Piola-Kirchhoff, engineering) stress is sigma/l.
enum class UniaxialLaw { NeoHookean, MooneyRivlin, Ogden };

// "neo-hookean" (or "neohookean"), "mooney-rivlin" ("mooneyrivlin"), "ogden"; throws InputError.
UniaxialLaw parseUniaxialLaw(std::string_view name);
std::string uniaxialLawName(UniaxialLaw law);  // "neo-hookean", ...
std::vector<std::string> uniaxialParameterNames(UniaxialLaw law);
std::vector<std::string> uniaxialParameterUnits(UniaxialLaw law);  // "Pa" or "-"

// Nominal stress (Pa) at stretch l > 0 and its gradient with respect to the parameters.
double uniaxialNominalStress(UniaxialLaw law, const Eigen::VectorXd& p, double l);
Eigen::VectorXd uniaxialNominalStressGradient(UniaxialLaw law, const Eigen::VectorXd& p, double l);

// Small-strain shear modulus (Pa): mu, 2 (c10 + c01) or mu; Young's modulus is 3 times it.
double uniaxialShearModulus(UniaxialLaw law, const Eigen::VectorXd& p);

}  // namespace bcassim
