// The spring priors of `bcassim ligament springs` (springs.yaml) as a scene reads them.
#include <gtest/gtest.h>

#include <string>

#include "bcassim/Error.h"
#include "bcassim/scene/LigamentSpringPriors.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

const char* kSpringPriorsYaml =
    "ligament_spring_priors:\n"
    "  rest_length: 0.1  # m\n"
    "  k_alpha: {mean: 5, stddev: 1}\n"
    "  k_beta: {mean: -2, stddev: 1}\n"
    "  k_gamma: {mean: 400, stddev: 20}\n"
    "  fit_error: 0.01\n"
    "  non_negative:\n"
    "    k_alpha: {mean: 3000, stddev: 300}\n"
    "    k_beta: {mean: 0, stddev: 0}\n"
    "    k_gamma: {mean: 4000, stddev: 80}\n"
    "    fit_error: 0.02\n";

std::string springPriorsError(const std::string& yaml) {
  const auto dir = test::freshDir();
  test::writeText(dir / "springs.yaml", yaml);
  try {
    readLigamentSpringPriors((dir / "springs.yaml").string());
  } catch (const InputError& e) {
    const std::string m = e.what();
    const std::string prefix = (dir / "springs.yaml").string();
    return m.rfind(prefix, 0) == 0 ? m.substr(prefix.size()) : m;
  }
  return "no error";
}

TEST(LigamentSpringPriors, ReadsTheNonNegativeFitAndScalesItToARestLength) {
  const auto dir = test::freshDir();
  test::writeText(dir / "springs.yaml", kSpringPriorsYaml);
  const LigamentSpringPriors p = readLigamentSpringPriors((dir / "springs.yaml").string());
  EXPECT_EQ(p.restLength, 0.1);
  EXPECT_EQ(p.kGamma.mean, 4000);
  EXPECT_EQ(p.kGamma.stddev, 80);
  EXPECT_EQ(p.kAlpha.mean, 3000);
  EXPECT_EQ(p.kBeta.mean, 0);
  // A strip half as long: the same force at the same strain, so twice the linear stiffness,
  // 4 times k_beta's and 8 times k_alpha's.
  const LigamentSpringPriors h = p.forRestLength(0.05);
  EXPECT_DOUBLE_EQ(h.restLength, 0.05);
  EXPECT_DOUBLE_EQ(h.kGamma.mean, 8000);
  EXPECT_DOUBLE_EQ(h.kGamma.stddev, 160);
  EXPECT_DOUBLE_EQ(h.kAlpha.mean, 24000);
  EXPECT_DOUBLE_EQ(h.kAlpha.stddev, 2400);
  // The force of one spring at a stretch of 10 % of its rest length is the strip's at 10 %.
  const double e = 0.1;
  auto force = [&](const LigamentSpringPriors& q) {
    const double d = e * q.restLength;
    return q.kAlpha.mean * d * d * d + q.kBeta.mean * d * d + q.kGamma.mean * d;
  };
  EXPECT_NEAR(force(h), force(p), 1e-12 * force(p));
}

TEST(LigamentSpringPriors, BadFilesAreOneLineNamingTheKey) {
  EXPECT_EQ(springPriorsError("rest_length: 0.1\n"),
            ":1: unknown key 'rest_length' in scene; expected one of ligament_spring_priors");
  std::string noSpread = kSpringPriorsYaml;
  noSpread.replace(noSpread.find("{mean: 4000, stddev: 80}"), 24, "{mean: 4000}");
  EXPECT_EQ(springPriorsError(noSpread),
            ":10: ligament_spring_priors.non_negative.k_gamma.stddev: missing (the prior's "
            "standard deviation per m of width)");
  std::string negative = kSpringPriorsYaml;
  negative.replace(negative.find("rest_length: 0.1"), 16, "rest_length: -1");
  EXPECT_EQ(springPriorsError(negative),
            ":2: ligament_spring_priors.rest_length: must be > 0 metres, got -1");
  EXPECT_EQ(springPriorsError("ligament_spring_priors: {rest_length: 0.1\n"), ":2: invalid YAML");
  EXPECT_EQ(springPriorsError("ligament_spring_priors: {rest_length: 0.1, non_negative: {}}\n"),
            ":1: ligament_spring_priors.non_negative.k_gamma: missing (the linear stiffness per "
            "m, N/m)");
}

}  // namespace
}  // namespace bcassim
