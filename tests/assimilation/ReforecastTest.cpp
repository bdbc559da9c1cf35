// The iterated analysis of RoukfOptions::reforecasts: a static model whose forecasts are
// linearised about its reference (as a static frame's chord steps are about the analysed
// mean's equilibrium). Re-centred on each analysed mean and forecast again, one frame's analysis
// is Gauss-Newton on its posterior: it reaches the maximum a posteriori estimate, with the
// Laplace covariance there, where the single analysis stays at the linearisation about the prior.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <string>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/Executor.h"
#include "bcassim/assimilation/RoukfFilter.h"

namespace bcassim {
namespace {

// y = h(theta) = (a^2, a b, b^2), the observable of a forecast linearised about the reference:
// h(ref) + J(ref) (theta - ref). The reference starts at `start`; recentre() moves it where the
// filter asks, when the model can.
class LinearisedAtItsReference final : public ForecastModel {
 public:
  LinearisedAtItsReference(const Eigen::Vector2d& start, bool canRecentre)
      : reference_(start), canRecentre_(canRecentre) {}
  static Eigen::Vector3d h(const Eigen::Vector2d& o) { return testing::Quadratic::h(o); }
  static Eigen::Matrix<double, 3, 2> jacobian(const Eigen::Vector2d& o) {
    return testing::Quadratic::jacobian(o);
  }
  Eigen::Index stateSize() const override { return 0; }
  Eigen::Index observableSize() const override { return 3; }
  void forecast(const Eigen::VectorXd&, const Eigen::VectorXd& params, Eigen::VectorXd& newState,
                Eigen::VectorXd& observable) override {
    newState.resize(0);
    observable = h(reference_) + jacobian(reference_) * (params - reference_);
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd& params) override {
    reference_ = params;
  }
  bool recentre(const Eigen::VectorXd&, const Eigen::VectorXd& params) override {
    if (!canRecentre_) return false;
    reference_ = params;
    ++recentres;
    return true;
  }
  int recentres = 0;

 private:
  Eigen::Vector2d reference_;
  bool canRecentre_;
};

const Eigen::Vector2d kMu(1.0, -0.5), kSd(0.4, 0.3);
constexpr double kSigma = 0.05;

StochasticState layout() {
  return StochasticState(Eigen::VectorXd(), Eigen::VectorXd(),
                         {{"a", kMu(0), kSd(0), {}}, {"b", kMu(1), kSd(1), {}}});
}

// The MAP of prior N(mu, diag(sd^2)) and y = h(theta) + N(0, sigma^2 I) by Gauss-Newton on its
// cost, written out here apart from the filter, and the Laplace covariance there.
struct Posterior {
  Eigen::Vector2d map;
  Eigen::Matrix2d covariance;
};
Posterior maximumAPosteriori(const Eigen::Vector3d& y) {
  using M = LinearisedAtItsReference;
  const Eigen::Matrix2d Pinv = kSd.array().square().inverse().matrix().asDiagonal();
  Eigen::Vector2d theta = kMu;
  Eigen::Matrix2d A;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Matrix<double, 3, 2> J = M::jacobian(theta);
    A = Pinv + J.transpose() * J / (kSigma * kSigma);
    theta -= A.ldlt().solve(Pinv * (theta - kMu) -
                            J.transpose() * (y - M::h(theta)) / (kSigma * kSigma));
  }
  const Eigen::Matrix<double, 3, 2> J = M::jacobian(theta);
  return {theta, (Pinv + J.transpose() * J / (kSigma * kSigma)).inverse()};
}

struct Analysis {
  Eigen::Vector2d mean;
  Eigen::Matrix2d covariance;
  FilterStepReport report;
  int recentres = 0;
};

Analysis analyse(const Eigen::Vector3d& y, int reforecasts, double tolerance = 0.1,
                 bool canRecentre = true) {
  LinearisedAtItsReference model(kMu, canRecentre);
  SerialExecutor serial;
  RoukfOptions o;
  o.reforecasts = reforecasts;
  o.relinearizationTolerance = tolerance;
  RoukfFilter roukf(layout(), {&model}, serial, o);
  Analysis run;
  run.report = roukf.step(Observation::withSigma(y, kSigma));
  run.mean = roukf.mean();
  run.covariance = roukf.covariance();
  run.recentres = model.recentres;
  return run;
}

// Far from the prior: the data say (1.5, -0.2), 1.25 and 1 prior standard deviations away.
const Eigen::Vector3d kFar = LinearisedAtItsReference::h(Eigen::Vector2d(1.5, -0.2));

TEST(Reforecasts, ReachTheMaximumAPosterioriWhereOneAnalysisStaysAtThePriorsLinearisation) {
  const Posterior exact = maximumAPosteriori(kFar);
  ASSERT_LT((LinearisedAtItsReference::h(exact.map) - kFar).norm(), 0.05);
  const auto spreadFromMap = [&](const Analysis& r) {
    const Eigen::Vector2d e = r.mean - exact.map;
    return std::sqrt(e.dot(r.covariance.ldlt().solve(e)));
  };

  const Analysis once = analyse(kFar, 0);
  EXPECT_EQ(once.report.reforecasts, 0);
  EXPECT_EQ(once.recentres, 0);
  EXPECT_GT(spreadFromMap(once), 1.0);

  // To a tolerance of 1e-10 analysed standard deviations: the MAP and its Laplace covariance,
  // the iterations stopped by the tolerance (each one re-centred the model first).
  const Analysis iterated = analyse(kFar, 40, 1e-10);
  EXPECT_LT((iterated.mean - exact.map).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((iterated.covariance - exact.covariance).cwiseAbs().maxCoeff(),
            1e-8 * exact.covariance.cwiseAbs().maxCoeff());
  EXPECT_GT(iterated.report.reforecasts, 1);
  EXPECT_LT(iterated.report.reforecasts, 40);
  EXPECT_EQ(iterated.recentres, iterated.report.reforecasts);

  // The default tolerance (0.1 of the analysed spread): within a fifth of it, in a few.
  const Analysis few = analyse(kFar, 40);
  EXPECT_LT(spreadFromMap(few), 0.2);
  EXPECT_LE(few.report.reforecasts, 6);
}

TEST(Reforecasts, AModelThatCannotRecentreKeepsTheSingleAnalysis) {
  const Analysis once = analyse(kFar, 0);
  const Analysis refused = analyse(kFar, 5, 0.1, false);
  EXPECT_EQ(refused.report.reforecasts, 0);
  EXPECT_EQ((refused.mean - once.mean).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((refused.covariance - once.covariance).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Reforecasts, AMoveWithinAForecastStandardDeviationIsNotForecastAgain) {
  // Data a third of a prior standard deviation from the prior mean.
  const Eigen::Vector3d near = LinearisedAtItsReference::h(kMu + Eigen::Vector2d(0.12, 0.09) / 3);
  const Analysis r = analyse(near, 5);
  EXPECT_EQ(r.report.reforecasts, 0);
  EXPECT_EQ(r.recentres, 0);
}

TEST(Reforecasts, BadOptionsAndAStateThatIsNotParametersAloneAreRefused) {
  LinearisedAtItsReference model(kMu, true);
  testing::Oscillator oscillator;
  SerialExecutor serial;
  const auto message = [&](const StochasticState& s, const RoukfOptions& o) {
    try {
      RoukfFilter roukf(
          s, {s.physicalSize() > 0 ? static_cast<ForecastModel*>(&oscillator) : &model}, serial, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  RoukfOptions o;
  o.reforecasts = -1;
  EXPECT_EQ(message(layout(), o), "reforecasts must be >= 0");
  o.reforecasts = 2;
  o.reforecastBeyond = 0;
  EXPECT_EQ(message(layout(), o),
            "reforecast_beyond must be a finite number > 0 (forecast standard deviations)");
  o.reforecastBeyond = std::nan("");
  EXPECT_EQ(message(layout(), o),
            "reforecast_beyond must be a finite number > 0 (forecast standard deviations)");
  o.reforecastBeyond = 1;
  // An oscillator's position and velocity in the state: a dynamic model's.
  const StochasticState withPositions(Eigen::Vector2d(0.1, 0), Eigen::Vector2d(0, 0),
                                      {{"k", 2.0, 0.5, {}}});
  EXPECT_EQ(message(withPositions, o),
            "reforecasts: only for a state of parameters alone (static frames); this one carries "
            "the mechanical state too");
}

}  // namespace
}  // namespace bcassim
