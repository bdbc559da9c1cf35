// Cubic spring priors per metre of ligament, as `bcassim ligament springs` writes them
// (springs.yaml, thesis §2.3.4, §4.4): what a scene's ligament springs start from when the
// tissue was measured, not guessed. SI units.
#pragma once
#include <string>

namespace bcassim {

struct SpringPriorPerMetre {
  double mean = 0, stddev = 0;  // per metre of ligament width
};

struct LigamentSpringPriors {
  double restLength = 0;  // m: the calibrated membrane's length, the springs' rest length
  // The fit with every coefficient >= 0 (`non_negative`, as springs.groups[] take them):
  // k_alpha N/m^3, k_beta N/m^2, k_gamma N/m, each per m of width.
  SpringPriorPerMetre kAlpha, kBeta, kGamma;

  // The same ligament with springs of rest length `length` (m): a strip stretched uniformly, so a
  // spring's force at a strain is the same, k_gamma scales as 1/length, k_beta as 1/length^2 and
  // k_alpha as 1/length^3.
  LigamentSpringPriors forRestLength(double length) const;
};

// Reads `ligament_spring_priors` of a springs.yaml. Throws InputError, one line naming the file,
// the line and the key: "<file>:<line>: ligament_spring_priors.non_negative.k_gamma.mean: ...".
LigamentSpringPriors readLigamentSpringPriors(const std::string& path);

}  // namespace bcassim
