#include "bcassim/scene/ModelParameter.h"

#include <fmt/format.h>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

// model.loads[index]; `kind` ("force", "footprint") names the parameter in the error.
template <class Model>
auto& loadOf(Model& model, int index, const char* kind) {
  if (index < 0 || index >= static_cast<int>(model.loads.size()))
    throw InputError(fmt::format("{} parameter: load {} does not exist ({} loads)", kind, index,
                                 model.loads.size()));
  return model.loads[static_cast<size_t>(index)];
}

}  // namespace

std::string defaultParameterName(const ModelParameterTarget& target) {
  if (const auto* e = std::get_if<YoungModulusTarget>(&target))
    return "E_" + std::to_string(e->region);
  if (const auto* f = std::get_if<LoadForceTarget>(&target))
    return std::string("F") + "xyz"[f->component] + "_" + std::to_string(f->load);
  if (const auto* f = std::get_if<LoadFootprintTarget>(&target)) {
    const char* names[] = {"tilt_u", "tilt_v", "concentration"};
    return std::string(names[f->coefficient]) + "_" + std::to_string(f->load);
  }
  if (const auto* o = std::get_if<ObservationPoseTarget>(&target)) {
    const char* names[] = {"rx", "ry", "rz", "tx", "ty", "tz"};
    return std::string("pose_") + names[o->component];
  }
  const auto& k = std::get<SpringCoefficientTarget>(target);
  const char* names[] = {"k_alpha", "k_beta", "k_gamma"};
  return std::string(names[k.coefficient]) + "_" + std::to_string(k.group);
}

void applyParameter(const ModelParameterTarget& target, double value, MechanicalModel& model) {
  if (const auto* e = std::get_if<YoungModulusTarget>(&target)) {
    if (e->region < 0 || e->region >= model.elasticity.numRegions())
      throw InputError(fmt::format("young_modulus parameter: region {} does not exist ({} regions)",
                                   e->region, model.elasticity.numRegions()));
    model.elasticity.setMaterial(e->region, makeMaterial(e->model, value, e->poissonRatio));
    return;
  }
  if (const auto* f = std::get_if<LoadForceTarget>(&target)) {
    NodalLoad& load = loadOf(model, f->load, "force");
    if (!load.frames.empty())
      throw InputError(fmt::format(
          "force parameter: load {} is given frame by frame; an estimated force needs a constant "
          "one",
          f->load));
    load.setTotalForce(f->component, value);
    return;
  }
  if (const auto* f = std::get_if<LoadFootprintTarget>(&target)) {
    NodalLoad& load = loadOf(model, f->load, "footprint");
    if (!load.frames.empty())
      throw InputError(fmt::format(
          "footprint parameter: load {} is given frame by frame; an estimated footprint needs a "
          "constant force",
          f->load));
    if (!load.footprint) {
      // From now on the weights share the total: forcePerNode holds the total force.
      const Vec3 total = load.totalForce();
      Eigen::MatrixX3d rest(static_cast<Eigen::Index>(load.nodes.size()), 3);
      for (size_t k = 0; k < load.nodes.size(); ++k)
        rest.row(static_cast<Eigen::Index>(k)) = model.mesh->V.row(load.nodes[k]);
      load.footprint.emplace(rest, load.weights);
      load.forcePerNode = total;
    }
    load.footprint->setCoefficient(f->coefficient, value);
    load.weights = load.footprint->shares();
    return;
  }
  if (std::holds_alternative<ObservationPoseTarget>(target)) return;  // not the mechanics
  const auto& k = std::get<SpringCoefficientTarget>(target);
  if (k.group < 0 || k.group >= model.springs.numGroups())
    throw InputError(fmt::format("spring parameter: group {} does not exist ({} groups)", k.group,
                                 model.springs.numGroups()));
  CubicSpringCoefficients c = model.springs.coefficients(k.group);
  (k.coefficient == 0 ? c.kAlpha : k.coefficient == 1 ? c.kBeta : c.kGamma) = value;
  model.springs.setCoefficients(k.group, c);
}

double readParameter(const ModelParameterTarget& target, const MechanicalModel& model) {
  if (const auto* e = std::get_if<YoungModulusTarget>(&target)) {
    // Young's modulus is not stored by the materials; recover it from the small-strain moduli.
    return std::visit(
        [&](const auto& m) -> double {
          if constexpr (requires {
                          m.lambda;
                          m.mu;
                        }) {
            return m.mu * (3 * m.lambda + 2 * m.mu) / (m.lambda + m.mu);
          } else {
            throw InputError("young_modulus parameter: the region's material is not given by E");
          }
        },
        model.elasticity.material(e->region));
  }
  if (const auto* f = std::get_if<LoadForceTarget>(&target)) {
    return loadOf(model, f->load, "force").totalForce()(f->component);
  }
  if (const auto* f = std::get_if<LoadFootprintTarget>(&target)) {
    const NodalLoad& load = loadOf(model, f->load, "footprint");
    return load.footprint ? load.footprint->coefficient(f->coefficient) : 0.0;
  }
  if (std::holds_alternative<ObservationPoseTarget>(target)) return 0.0;
  const auto& k = std::get<SpringCoefficientTarget>(target);
  const CubicSpringCoefficients c = model.springs.coefficients(k.group);
  return k.coefficient == 0 ? c.kAlpha : k.coefficient == 1 ? c.kBeta : c.kGamma;
}

}  // namespace bcassim
