#include "bcassim/scene/LigamentSpringPriors.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/scene/YamlReader.h"

namespace bcassim {
namespace {

using yamlio::MapReader;
using yamlio::Range;

// `spread`: the range of the standard deviation (Positive for a coefficient to estimate).
SpringPriorPerMetre readPrior(const MapReader& parent, const std::string& key,
                              const std::string& unit, Range spread = Range::NonNegative) {
  const MapReader m(parent.source(), parent.node(key), parent.pathOf(key), {"mean", "stddev"});
  if (!m.has("mean")) m.fail("mean", "missing (the prior's mean per m of width)");
  if (spread == Range::Positive && !m.has("stddev"))
    m.fail("stddev", "missing (the prior's standard deviation per m of width)");
  return {m.number("mean", 0.0, unit, Range::NonNegative), m.number("stddev", 0.0, unit, spread)};
}

}  // namespace

LigamentSpringPriors LigamentSpringPriors::forRestLength(double length) const {
  const double r = restLength / length;
  LigamentSpringPriors p = *this;
  p.restLength = length;
  p.kGamma = {kGamma.mean * r, kGamma.stddev * r};
  p.kBeta = {kBeta.mean * r * r, kBeta.stddev * r * r};
  p.kAlpha = {kAlpha.mean * r * r * r, kAlpha.stddev * r * r * r};
  return p;
}

LigamentSpringPriors readLigamentSpringPriors(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the spring priors (springs.yaml)");
  std::stringstream text;
  text << in.rdbuf();
  const yamlio::YamlSource src{path, std::filesystem::path(path).parent_path().string()};
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": invalid YAML");
  }
  const MapReader top(src, root, "", {"ligament_spring_priors"});
  if (!top.has("ligament_spring_priors"))
    top.fail("ligament_spring_priors",
             "missing (the priors of `bcassim ligament springs`, springs.yaml)");
  const MapReader p(src, top.node("ligament_spring_priors"), "ligament_spring_priors",
                    {"rest_length", "k_alpha", "k_beta", "k_gamma", "fit_error", "non_negative",
                     "lattice", "comparison"});
  LigamentSpringPriors out;
  if (!p.has("rest_length")) p.fail("rest_length", "missing (the springs' rest length, m)");
  out.restLength = p.number("rest_length", 0.0, "m", Range::Positive);
  if (!p.has("non_negative"))
    p.fail("non_negative", "missing (the fit with coefficients >= 0 that springs take)");
  const MapReader nn(src, p.node("non_negative"), p.pathOf("non_negative"),
                     {"k_alpha", "k_beta", "k_gamma", "fit_error"});
  if (!nn.has("k_gamma")) nn.fail("k_gamma", "missing (the linear stiffness per m, N/m)");
  out.kAlpha = nn.has("k_alpha") ? readPrior(nn, "k_alpha", "N/m^3") : SpringPriorPerMetre{};
  out.kBeta = nn.has("k_beta") ? readPrior(nn, "k_beta", "N/m^2") : SpringPriorPerMetre{};
  out.kGamma = readPrior(nn, "k_gamma", "N/m", Range::Positive);
  if (!(out.kGamma.mean > 0))
    nn.fail("k_gamma", "the linear stiffness must be positive to start a ligament from");
  return out;
}

}  // namespace bcassim
