#include "bcassim/calibration/UniaxialLaw.h"

#include <fmt/format.h>

#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

UniaxialLaw parseUniaxialLaw(std::string_view name) {
  if (name == "neo-hookean" || name == "neohookean") return UniaxialLaw::NeoHookean;
  if (name == "mooney-rivlin" || name == "mooneyrivlin") return UniaxialLaw::MooneyRivlin;
  if (name == "ogden") return UniaxialLaw::Ogden;
  throw InputError(fmt::format("model '{}': expected neo-hookean, mooney-rivlin or ogden", name));
}

std::string uniaxialLawName(UniaxialLaw law) {
  switch (law) {
    case UniaxialLaw::NeoHookean:
      return "neo-hookean";
    case UniaxialLaw::MooneyRivlin:
      return "mooney-rivlin";
    case UniaxialLaw::Ogden:
      return "ogden";
  }
  return "";
}

std::vector<std::string> uniaxialParameterNames(UniaxialLaw law) {
  switch (law) {
    case UniaxialLaw::NeoHookean:
      return {"mu"};
    case UniaxialLaw::MooneyRivlin:
      return {"c10", "c01"};
    case UniaxialLaw::Ogden:
      return {"mu", "alpha"};
  }
  return {};
}

std::vector<std::string> uniaxialParameterUnits(UniaxialLaw law) {
  return law == UniaxialLaw::Ogden
             ? std::vector<std::string>{"Pa", "-"}
             : std::vector<std::string>(uniaxialParameterNames(law).size(), "Pa");
}

namespace {
// (l^a - l^(-a/2)) / a and its derivative in a; near a = 0 the series 1.5 ln l + ... keeps it
// finite and accurate (the quotient would cancel).
void ogdenShape(double l, double a, double& value, double& dValue) {
  const double L = std::log(l);
  if (std::abs(a * L) < 1e-4) {
    // (e^(aL) - e^(-aL/2)) / a = 3/2 L + 3/8 a L^2 + 3/16 a^2 L^3 + O(a^3)
    value = 1.5 * L + 0.375 * a * L * L + 0.1875 * a * a * L * L * L;
    dValue = 0.375 * L * L + 0.375 * a * L * L * L;
    return;
  }
  const double up = std::exp(a * L), down = std::exp(-0.5 * a * L);
  value = (up - down) / a;
  dValue = (L * up + 0.5 * L * down) / a - (up - down) / (a * a);
}
}  // namespace

double uniaxialNominalStress(UniaxialLaw law, const Eigen::VectorXd& p, double l) {
  switch (law) {
    case UniaxialLaw::NeoHookean:
      return p(0) * (l - 1.0 / (l * l));
    case UniaxialLaw::MooneyRivlin:
      return 2.0 * (l - 1.0 / (l * l)) * (p(0) + p(1) / l);
    case UniaxialLaw::Ogden: {
      double shape = 0, dShape = 0;
      ogdenShape(l, p(1), shape, dShape);
      return 2.0 * p(0) * shape / l;
    }
  }
  return 0.0;
}

Eigen::VectorXd uniaxialNominalStressGradient(UniaxialLaw law, const Eigen::VectorXd& p, double l) {
  Eigen::VectorXd g(p.size());
  switch (law) {
    case UniaxialLaw::NeoHookean:
      g(0) = l - 1.0 / (l * l);
      break;
    case UniaxialLaw::MooneyRivlin:
      g(0) = 2.0 * (l - 1.0 / (l * l));
      g(1) = g(0) / l;
      break;
    case UniaxialLaw::Ogden: {
      double shape = 0, dShape = 0;
      ogdenShape(l, p(1), shape, dShape);
      g(0) = 2.0 * shape / l;
      g(1) = 2.0 * p(0) * dShape / l;
      break;
    }
  }
  return g;
}

double uniaxialShearModulus(UniaxialLaw law, const Eigen::VectorXd& p) {
  return law == UniaxialLaw::MooneyRivlin ? 2.0 * (p(0) + p(1)) : p(0);
}

}  // namespace bcassim
