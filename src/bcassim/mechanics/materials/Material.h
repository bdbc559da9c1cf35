// The closed set of materials a scene can name, as one value type: the FEM visits it once per
// region so each per-element loop is compiled for the concrete law.
#pragma once
#include <cmath>
#include <string>
#include <string_view>
#include <variant>

#include "bcassim/Error.h"
#include "bcassim/mechanics/materials/CorotationalMaterial.h"
#include "bcassim/mechanics/materials/LinearMaterial.h"
#include "bcassim/mechanics/materials/MooneyRivlinMaterial.h"
#include "bcassim/mechanics/materials/NeoHookeanMaterial.h"
#include "bcassim/mechanics/materials/OgdenMaterial.h"
#include "bcassim/mechanics/materials/StvkMaterial.h"

namespace bcassim {

using Material = std::variant<LinearMaterial, CorotationalMaterial, StvkMaterial,
                              NeoHookeanMaterial, MooneyRivlinMaterial, OgdenMaterial>;

inline const char* materialName(const Material& m) {
  return std::visit([](const auto& x) { return std::decay_t<decltype(x)>::name(); }, m);
}

namespace detail {
template <std::size_t I = 0>
bool makeMaterialByName(std::string_view name, double E, double nu, Material& out) {
  if constexpr (I == std::variant_size_v<Material>) {
    return false;
  } else {
    using M = std::variant_alternative_t<I, Material>;
    if (name == M::name()) {
      out = M::fromYoungPoisson(E, nu);
      return true;
    }
    return makeMaterialByName<I + 1>(name, E, nu, out);
  }
}

template <std::size_t I = 0>
std::string materialNameList() {
  if constexpr (I == std::variant_size_v<Material>) {
    return {};
  } else {
    std::string rest = materialNameList<I + 1>();
    std::string self = std::variant_alternative_t<I, Material>::name();
    return rest.empty() ? self : self + ", " + rest;
  }
}
}  // namespace detail

// Material `name` ("linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden") with
// Young's modulus E (Pa) and Poisson's ratio nu; Mooney-Rivlin and Ogden get the thesis' shape
// parameters (c01/c10, alpha) and the same small-strain shear and bulk moduli.
// Throws InputError for an unknown name or E <= 0, nu outside (-1, 0.5).
inline Material makeMaterial(std::string_view name, double E, double nu) {
  if (!(std::isfinite(E) && E > 0.0))
    throw InputError("material '" + std::string(name) + "': Young's modulus must be > 0 Pa, got " +
                     std::to_string(E));
  if (!(nu > -1.0 && nu < 0.5))
    throw InputError("material '" + std::string(name) +
                     "': Poisson's ratio must be in (-1, 0.5), got " + std::to_string(nu));
  Material m;
  if (!detail::makeMaterialByName(name, E, nu, m))
    throw InputError("unknown material '" + std::string(name) + "'; expected one of " +
                     detail::materialNameList());
  return m;
}

}  // namespace bcassim
