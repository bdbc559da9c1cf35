// What an estimated scalar sets in the mechanical model: a region's Young's modulus or one
// coefficient of a spring group (thesis §3.4: E; [k_alpha, k_beta, k_gamma] shared by springs).
#pragma once
#include <string>
#include <variant>

#include "bcassim/mechanics/MechanicalModel.h"

namespace bcassim {

// Young's modulus (Pa) of the tets of `region`, the material rebuilt with `model` and ν.
struct YoungModulusTarget {
  int region = 0;
  std::string model = "stvk";
  double poissonRatio = 0.49;
};

// One coefficient of a spring group: 0 = k_alpha (N/m^3), 1 = k_beta (N/m^2), 2 = k_gamma (N/m).
struct SpringCoefficientTarget {
  int group = 0;
  int coefficient = 0;
};

using ModelParameterTarget = std::variant<YoungModulusTarget, SpringCoefficientTarget>;

// The name an estimated parameter gets unless the scene names it: E_<region>, k_alpha_<group>,
// k_beta_<group> or k_gamma_<group>.
std::string defaultParameterName(const ModelParameterTarget& target);

// Writes the physical value into the model. Throws InputError if the target does not exist.
void applyParameter(const ModelParameterTarget& target, double value, MechanicalModel& model);
// Reads the model's current value of the target (used to report the true value of a scene).
double readParameter(const ModelParameterTarget& target, const MechanicalModel& model);

}  // namespace bcassim
