// Parameter transforms round-trip values and standard deviations, and their slopes match finite
// differences; the stochastic state lays out and reports parameters through them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/assimilation/StochasticState.h"

namespace bcassim {
namespace {

std::vector<ParameterTransform> allTransforms() {
  return {ParameterTransform::identity(), ParameterTransform::absolute(),
          ParameterTransform::exponential(), ParameterTransform::projection(0.5, 50.0),
          ParameterTransform::boundedLog(0.5, 50.0)};
}

TEST(ParameterTransform, ValuesAndStddevsRoundTrip) {
  for (const ParameterTransform& t : allTransforms()) {
    for (double value : {0.7, 1.0, 4.0, 13.5, 49.0}) {
      const double u = t.toUnconstrained(value);
      EXPECT_NEAR(t.toPhysical(u), value, 1e-12 * value);
      for (double sd : {0.01, 0.3, 2.0}) {
        const double sdU = t.stddevToUnconstrained(value, sd);
        EXPECT_NEAR(t.stddevToPhysical(u, sdU), sd, 1e-12 * sd);
      }
    }
  }
}

TEST(ParameterTransform, SlopeMatchesFiniteDifferences) {
  for (const ParameterTransform& t : allTransforms()) {
    for (double u : {-2.0, -0.3, 0.8, 1.7, 3.0, 60.0}) {
      const double h = 1e-6;
      const double fd = (t.toPhysical(u + h) - t.toPhysical(u - h)) / (2 * h);
      EXPECT_NEAR(t.slope(u), fd, 1e-6 * std::max(1.0, std::abs(fd)))
          << static_cast<int>(t.kind()) << " u=" << u;
    }
  }
}

TEST(ParameterTransform, ExponentialPushesSigmaAsRelativeSpread) {
  const ParameterTransform t = ParameterTransform::exponential();
  EXPECT_NEAR(t.stddevToUnconstrained(4000.0, 400.0), 0.1, 1e-15);  // 10 % in log space
  EXPECT_NEAR(t.toPhysical(t.toUnconstrained(4000.0) + 0.1), 4000.0 * std::exp(0.1), 1e-9);
}

TEST(ParameterTransform, RejectsValuesOutsideItsRange) {
  EXPECT_THROW(ParameterTransform::exponential().toUnconstrained(0.0), InputError);
  EXPECT_THROW(ParameterTransform::absolute().toUnconstrained(-1.0), InputError);
  EXPECT_THROW(ParameterTransform::projection(1, 2).toUnconstrained(3.0), InputError);
  EXPECT_THROW(ParameterTransform::projection(2, 1), InputError);
  EXPECT_EQ(parseTransformKind("log"), TransformKind::Exponential);
  EXPECT_EQ(parseTransformKind("abs"), TransformKind::Absolute);
  EXPECT_EQ(parseTransformKind("bounded-log"), TransformKind::BoundedLog);
  EXPECT_THROW(parseTransformKind("sqrt"), InputError);
}

TEST(ParameterTransform, ProjectionAndAbsoluteKeepThePhysicalValueInRange) {
  const ParameterTransform box = ParameterTransform::projection(1.0, 2.0);
  EXPECT_EQ(box.toPhysical(-5.0), 1.0);
  EXPECT_EQ(box.toPhysical(7.0), 2.0);
  EXPECT_EQ(ParameterTransform::absolute().toPhysical(-3.0), 3.0);
}

// physical = exp(a + (b - a) sigma(u)): at u = 0 the geometric mean sqrt(lo hi) with slope
// sqrt(lo hi) ln(hi / lo) / 4 (sigma'(0) = 1/4); at u = +-ln 3 (sigma = 3/4, 1/4) the values
// lo^(1/4) hi^(3/4) and lo^(3/4) hi^(1/4).
TEST(ParameterTransform, BoundedLogAnalyticValues) {
  const double lo = 2.0, hi = 2e6;
  const ParameterTransform t = ParameterTransform::boundedLog(lo, hi);
  EXPECT_EQ(t.kind(), TransformKind::BoundedLog);
  EXPECT_NEAR(t.toPhysical(0.0), 2e3, 1e-12 * 2e3);
  EXPECT_NEAR(t.slope(0.0), 2e3 * std::log(1e6) / 4, 1e-12 * 2e3);
  EXPECT_NEAR(t.toPhysical(std::log(3.0)), std::pow(lo, 0.25) * std::pow(hi, 0.75), 1e-9 * hi);
  EXPECT_NEAR(t.toPhysical(-std::log(3.0)), std::pow(lo, 0.75) * std::pow(hi, 0.25), 1e-9 * hi);
  EXPECT_NEAR(t.toUnconstrained(2e3), 0.0, 1e-12);
  EXPECT_NEAR(t.toUnconstrained(std::pow(lo, 0.25) * std::pow(hi, 0.75)), std::log(3.0), 1e-12);
  // A prior at the centre with a standard deviation equal to its mean: 1 in log space, i.e.
  // 4 / ln(hi / lo) in u.
  EXPECT_NEAR(t.stddevToUnconstrained(2e3, 2e3), 4 / std::log(1e6), 1e-15);
}

// Sigma points anywhere on the real line map into [lo, hi] and, unlike a clamp, keep a
// positive slope: the filter still sees how the model responds to them.
TEST(ParameterTransform, BoundedLogStaysInsideItsBoundsWithAPositiveSlope) {
  const double lo = 0.3, hi = 300.0;
  const ParameterTransform t = ParameterTransform::boundedLog(lo, hi);
  double previous = 0.0;
  for (double u = -30.0; u <= 30.0; u += 0.25) {
    const double v = t.toPhysical(u);
    EXPECT_GE(v, lo) << "u=" << u;
    EXPECT_LE(v, hi) << "u=" << u;
    EXPECT_GT(v, previous) << "u=" << u;  // strictly increasing: one value per u
    EXPECT_GT(t.slope(u), 0.0) << "u=" << u;
    previous = v;
  }
  EXPECT_DOUBLE_EQ(t.toPhysical(1e6), hi);
  EXPECT_DOUBLE_EQ(t.toPhysical(-1e6), lo);
  EXPECT_EQ(t.slope(1e6), 0.0);  // sigma'(u) underflows only far outside any sigma point
}

TEST(ParameterTransform, BoundedLogRejectsItsBoundsAndBadBounds) {
  const ParameterTransform t = ParameterTransform::boundedLog(1.0, 4.0);
  EXPECT_THROW(t.toUnconstrained(1.0), InputError);
  EXPECT_THROW(t.toUnconstrained(4.0), InputError);
  EXPECT_THROW(t.toUnconstrained(0.5), InputError);
  try {
    t.toUnconstrained(5.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "value 5 lies outside (1, 4); a bounded-log parameter is strictly inside its "
                 "bounds");
  }
  EXPECT_THROW(ParameterTransform::boundedLog(0.0, 1.0), InputError);   // log of 0
  EXPECT_THROW(ParameterTransform::boundedLog(-1.0, 1.0), InputError);  // log of a negative
  EXPECT_THROW(ParameterTransform::boundedLog(2.0, 2.0), InputError);
  EXPECT_THROW(ParameterTransform::boundedLog(1.0, INFINITY), InputError);
}

TEST(StochasticState, LaysOutPhysicalPartThenUnconstrainedParameters) {
  const StochasticState s(Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(0.0, 0.01),
                          {{"E", 4000.0, 350.0, ParameterTransform::exponential()},
                           {"k", 7.0, 2.0, ParameterTransform::identity()}});
  EXPECT_EQ(s.size(), 4);
  const Eigen::VectorXd x = s.initialMean();
  EXPECT_NEAR(x[2], std::log(4000.0), 1e-15);
  EXPECT_NEAR(s.initialStddev()[2], 350.0 / 4000.0, 1e-15);
  Eigen::VectorXd params, mean, sd;
  s.physicalParameters(x, params);
  EXPECT_NEAR(params[0], 4000.0, 1e-9);
  EXPECT_EQ(params[1], 7.0);
  s.toReported(x, s.initialStddev(), mean, sd);
  EXPECT_NEAR(sd[2], 350.0, 1e-9);
  EXPECT_EQ(mean[0], 0.1);
  EXPECT_THROW(StochasticState(Eigen::Vector2d(0, 0), Eigen::VectorXd(1), {}), InputError);
  EXPECT_THROW(StochasticState({}, {}, {{"k", 1.0, 0.0, {}}}), InputError);
  EXPECT_THROW(StochasticState({}, {}, {{"k", -1.0, 1.0, ParameterTransform::exponential()}}),
               InputError);
}

}  // namespace
}  // namespace bcassim
