// What an estimated scalar sets in the mechanical model: a region's Young's modulus, one
// coefficient of a spring group (thesis §3.4: E; [k_alpha, k_beta, k_gamma] shared by springs) or
// one component of a load's total force (an unknown tool force, issue 14), or one coefficient of
// how that force is shared over the load's zone (the tool's footprint); or one coordinate of the
// observations' pose (not a mechanical parameter: what the model is compared with moves).
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

// One component (0, 1, 2 = x, y, z) of the total force (N) of model.loads[load], shared over its
// nodes as the load says (evenly, or by its surface weights); see NodalLoad::setTotalForce.
struct LoadForceTarget {
  int load = 0;
  int component = 0;
};

// One coefficient of how model.loads[load] shares its total force (LoadFootprint.h): 0 = tilt along
// the zone's first in-plane axis, 1 = along the second, 2 = concentration; dimensionless, 0 = the
// load's own split.
struct LoadFootprintTarget {
  int load = 0;
  int coefficient = 0;
};

// One coordinate of a small rigid motion between the model's frame and the observations' (the
// residual error of a camera's registration): 0, 1, 2 = the rotation vector's x, y, z (rad, about
// the model's rest centroid), 3, 4, 5 = the translation (m). It moves what the model shows the
// observations (coupling/MechanicalForecastModel), never the mechanics: applyParameter leaves the
// model as it is.
struct ObservationPoseTarget {
  int component = 0;
};

using ModelParameterTarget =
    std::variant<YoungModulusTarget, SpringCoefficientTarget, LoadForceTarget, LoadFootprintTarget,
                 ObservationPoseTarget>;

// The name an estimated parameter gets unless the scene names it: E_<region>, k_alpha_<group>,
// k_beta_<group>, k_gamma_<group>, F<x|y|z>_<load>, tilt_u_<load>, tilt_v_<load>,
// concentration_<load>, or pose_<rx|ry|rz|tx|ty|tz>.
std::string defaultParameterName(const ModelParameterTarget& target);

// Writes the physical value into the model. Throws InputError if the target does not exist.
void applyParameter(const ModelParameterTarget& target, double value, MechanicalModel& model);
// Reads the model's current value of the target (used to report the true value of a scene); 0 for
// a pose coordinate (the model's own frame).
double readParameter(const ModelParameterTarget& target, const MechanicalModel& model);

}  // namespace bcassim
