// A step whose forecasts fail far from the mean (as a sigma point that inverts an element) is
// redone with the points closer to the mean: on a linear model the filters are then still the
// exact Kalman filter, and the report says how far the points were pulled in and why; without
// retries, or once they are spent, the step ends with the model's own error.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/SimplexSigmaPoints.h"
#include "bcassim/assimilation/UkfFilter.h"

namespace bcassim {
namespace {
using testing::exactFor;
using testing::ExactKalman;
using testing::kLinearSteps;
using testing::kLinearTheta;
using testing::linearLayout;
using testing::LinearModel;
using testing::LinearSystem;

// The linear model, failing like an integrator that gave up on a step (StepFailure is a
// NumericalError) whenever parameter 0 is more than `reach` from the last analysed mean's.
class FailingFarOut final : public ForecastModel {
 public:
  FailingFarOut(const LinearSystem& s, double prior, double reach)
      : inner_(s), mean_(prior), reach_(reach) {}
  Eigen::Index stateSize() const override { return inner_.stateSize(); }
  Eigen::Index observableSize() const override { return inner_.observableSize(); }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& predicted) override {
    ++calls_;
    if (std::abs(params(0) - mean_) > reach_)
      throw NumericalError("element 7 inverted at the time step 1e-05 s");
    inner_.forecast(state, params, newState, predicted);
  }
  int calls() const { return calls_; }
  void endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) override {
    mean_ = params(0);
    inner_.endStep(state, params);
  }

 private:
  LinearModel inner_;
  double mean_, reach_;
  int calls_ = 0;
};

// The three filters on the same model and prior (the ETKF's members carry the prior's moments
// exactly, so that it too is the Kalman filter).
std::unique_ptr<Filter> makeFilter(const std::string& kind, const StochasticState& layout,
                                   ForecastModel& model, Executor& executor, int retries) {
  if (kind == "roukf") {
    RoukfOptions o;
    o.forecastRetries = retries;
    return std::make_unique<RoukfFilter>(layout, std::vector<ForecastModel*>{&model}, executor, o);
  }
  if (kind == "ukf") {
    UkfOptions o;
    o.sigmaPoints = SigmaPointKind::Simplex;
    o.forecastRetries = retries;
    return std::make_unique<UkfFilter>(layout, std::vector<ForecastModel*>{&model}, executor, o);
  }
  const SigmaPointSet simplex = simplexSigmaPoints(layout.size());
  const double N = static_cast<double>(simplex.count());
  EtkfOptions o;
  o.members = static_cast<int>(N);
  o.forecastRetries = retries;
  auto etkf =
      std::make_unique<EtkfFilter>(layout, std::vector<ForecastModel*>{&model}, executor, o);
  etkf->reset(
      simplex.points(layout.initialMean(),
                     std::sqrt((N - 1) / N) * layout.initialStddev().asDiagonal().toDenseMatrix()));
  return etkf;
}

// What a step that must fail says (NumericalError's message; "no error" when it went through).
std::string stepError(Filter& filter, const Observation& y) {
  try {
    filter.step(y);
  } catch (const NumericalError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ForecastRetry, FailedForecastsRedoneCloserToTheMeanKeepEveryFilterExact) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
  const StochasticState layout = linearLayout(0.1);
  for (const std::string kind : {"roukf", "ukf", "etkf"}) {
    // The prior's points reach about 0.4 * sqrt(5) = 0.9 from the mean in parameter a: 0.3 fails
    // them at full spread.
    FailingFarOut model(s, 0.5, 0.3);
    SerialExecutor serial;
    auto filter = makeFilter(kind, layout, model, serial, 3);
    ExactKalman kf = exactFor(s, layout);
    int retriedSteps = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const FilterStepReport report = filter->step(frames[i]);
      kf.step(frames[i]);
      EXPECT_LT((filter->mean() - kf.mean()).cwiseAbs().maxCoeff(), 1e-9) << kind << " step " << i;
      EXPECT_LT((filter->covariance() - kf.covariance()).cwiseAbs().maxCoeff(), 1e-9)
          << kind << " step " << i;
      if (report.forecastHalvings > 0) {
        ++retriedSteps;
        EXPECT_EQ(report.forecastFailure, "element 7 inverted at the time step 1e-05 s") << kind;
      } else {
        EXPECT_EQ(report.forecastFailure, "") << kind;
      }
    }
    // The prior's spread fails, the analysed one (a few steps later) no longer does.
    EXPECT_GE(retriedSteps, 1) << kind;
    EXPECT_LT(retriedSteps, kLinearSteps) << kind;
  }
}

TEST(ForecastRetry, WithoutRetriesTheModelsOwnErrorEndsTheStep) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, 1, 0.05);
  for (const std::string kind : {"roukf", "ukf", "etkf"}) {
    FailingFarOut model(s, 0.5, 0.3);
    SerialExecutor serial;
    auto filter = makeFilter(kind, linearLayout(0.1), model, serial, 0);
    EXPECT_EQ(stepError(*filter, frames[0]), "element 7 inverted at the time step 1e-05 s") << kind;
  }
}

TEST(ForecastRetry, SpentRetriesEndTheStepWithTheModelsOwnError) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, 1, 0.05);
  for (const std::string kind : {"roukf", "ukf", "etkf"}) {
    FailingFarOut model(s, 0.5, 1e-6);  // fails unless the points sit on the mean
    SerialExecutor serial;
    auto filter = makeFilter(kind, linearLayout(0.1), model, serial, 2);
    EXPECT_EQ(stepError(*filter, frames[0]), "element 7 inverted at the time step 1e-05 s") << kind;
    EXPECT_EQ(model.calls(), 3) << kind;  // the first try and two retries, each failing at once
  }
}

// A model's own error type (as the integrators' StepFailure), thrown where the step ends.
class MeansStepFailure : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

class FailingAtTheMean final : public ForecastModel {
 public:
  explicit FailingAtTheMean(const LinearSystem& s) : inner_(s) {}
  Eigen::Index stateSize() const override { return inner_.stateSize(); }
  Eigen::Index observableSize() const override { return inner_.observableSize(); }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& predicted) override {
    inner_.forecast(state, params, newState, predicted);
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override {
    throw MeansStepFailure("static solver at t = 0 s: Newton did not converge");
  }

 private:
  LinearModel inner_;
};

// The end of a step is not a forecast: its failure is named for the analysed mean and loses the
// model's type, which a runner reads as a sigma point's (and would say "after N tries").
TEST(ForecastRetry, AFailureAtTheAnalysedMeanIsNotAForecasts) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, 1, 0.05);
  for (const std::string kind : {"roukf", "ukf", "etkf"}) {
    FailingAtTheMean model(s);
    SerialExecutor serial;
    auto filter = makeFilter(kind, linearLayout(0.1), model, serial, 3);
    try {
      filter->step(frames[0]);
      ADD_FAILURE() << kind << ": no error";
    } catch (const MeansStepFailure&) {
      ADD_FAILURE() << kind << ": the model's type came through";
    } catch (const NumericalError& e) {
      EXPECT_STREQ(e.what(), "the analysed mean: static solver at t = 0 s: Newton did not converge")
          << kind;
    }
  }
}

TEST(ForecastRetry, NegativeRetriesAreRefused) {
  const LinearSystem s = LinearSystem::make();
  LinearModel model(s);
  SerialExecutor serial;
  for (const std::string kind : {"roukf", "ukf", "etkf"}) {
    try {
      makeFilter(kind, linearLayout(0.1), model, serial, -1);
      ADD_FAILURE() << kind << ": accepted";
    } catch (const InputError& e) {
      EXPECT_STREQ(e.what(), "forecast retries must be >= 0") << kind;
    }
  }
}

}  // namespace
}  // namespace bcassim
