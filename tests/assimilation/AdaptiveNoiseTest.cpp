// Adaptive observation noise (issue 15): each filter reports tr(H P H^T) of its prediction exactly,
// and InnovationNoiseEstimator fed by its step reports finds the data's noise on the linear
// Gaussian model whatever sigma the filter assumed at first; its floor holds on noise-free data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/InnovationNoiseEstimator.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/UkfFilter.h"

namespace bcassim {
namespace {
using testing::LinearModel;
using testing::LinearSystem;

const Eigen::Vector2d kAdaptiveNoiseTheta(1.0, -0.5);

StochasticState adaptiveNoiseLayout() {
  return StochasticState(Eigen::Vector3d(0.2, -0.1, 0.0), Eigen::Vector3d::Constant(0.1),
                         {{"a", 0.5, 0.4, {}}, {"b", 0.0, 0.3, {}}});
}

// Frames of a true run with noise `sigma` (0: none) on every entry; every 7th frame misses entry 1,
// every 11th is empty. Their variance is set by the caller before each step. `drawn` gets the
// square sum of each frame's noise over its present entries, and their count.
std::vector<Observation> adaptiveNoiseFrames(const LinearSystem& s, int steps, double sigma,
                                             std::vector<Eigen::Vector2d>* drawn = nullptr) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd x = Eigen::Vector3d(0.3, -0.2, 0.1);
  std::vector<Observation> frames;
  for (int i = 0; i < steps; ++i) {
    x = s.A * x + s.B * kAdaptiveNoiseTheta + s.forcing(i);
    Eigen::VectorXd noise(s.H.rows());
    for (Eigen::Index k = 0; k < noise.size(); ++k) noise[k] = sigma * normal(rng);
    Observation y = Observation::withSigma(s.H * x + noise, 1.0);
    if (i % 7 == 3) {
      y.present = {true, false, true, true};
      y.values[1] = std::nan("");
      noise[1] = 0.0;
    }
    const bool empty = i % 11 == 5;
    if (empty) y = Observation::none();
    if (drawn)
      drawn->push_back(empty ? Eigen::Vector2d(0, 0)
                             : Eigen::Vector2d(noise.squaredNorm(), i % 7 == 3 ? 3 : 4));
    frames.push_back(y);
  }
  return frames;
}

// The standard deviation of the noise actually drawn in the last `window` observed frames up to
// frame `last`: what the estimate can at best find.
double adaptiveNoiseDrawnSigma(const std::vector<Eigen::Vector2d>& drawn, int last, int window) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int i = last, seen = 0; i >= 0 && seen < window; --i)
    if (drawn[static_cast<size_t>(i)][1] > 0) {
      sum += drawn[static_cast<size_t>(i)];
      ++seen;
    }
  return std::sqrt(sum[0] / sum[1]);
}

enum class AdaptiveNoiseFilter { Ukf, Roukf, Etkf };
const char* adaptiveNoiseName(AdaptiveNoiseFilter f) {
  return f == AdaptiveNoiseFilter::Ukf ? "ukf" : f == AdaptiveNoiseFilter::Roukf ? "roukf" : "etkf";
}

std::unique_ptr<Filter> adaptiveNoiseFilter(AdaptiveNoiseFilter kind, LinearModel& model,
                                            Executor& executor) {
  switch (kind) {
    case AdaptiveNoiseFilter::Ukf:
      return std::make_unique<UkfFilter>(adaptiveNoiseLayout(), std::vector<ForecastModel*>{&model},
                                         executor);
    case AdaptiveNoiseFilter::Roukf:
      return std::make_unique<RoukfFilter>(adaptiveNoiseLayout(),
                                           std::vector<ForecastModel*>{&model}, executor);
    case AdaptiveNoiseFilter::Etkf: {
      EtkfOptions o;
      o.members = 20;
      return std::make_unique<EtkfFilter>(adaptiveNoiseLayout(),
                                          std::vector<ForecastModel*>{&model}, executor, o);
    }
  }
  return nullptr;
}

// The run with the noise each step assumes taken from the estimator; the sigma after every step.
std::vector<double> adaptiveNoiseRun(AdaptiveNoiseFilter kind,
                                     const std::vector<Observation>& frames,
                                     InnovationNoiseEstimator& noise) {
  const LinearSystem s = LinearSystem::make();
  LinearModel model(s);
  SerialExecutor serial;
  const std::unique_ptr<Filter> filter = adaptiveNoiseFilter(kind, model, serial);
  std::vector<double> sigmas;
  for (Observation y : frames) {
    if (y.values.size() > 0) y.variance.setConstant(noise.variance());
    const FilterStepReport report = filter->step(y);
    noise.add(report.innovationSquaredNorm, report.observed, report.predictedObservationTrace);
    sigmas.push_back(noise.sigma());
  }
  return sigmas;
}

TEST(AdaptiveNoise, EachFilterReportsTheTraceOfItsPredictedObservations) {
  // tr(H F P F^T H^T) over the present rows, P the filter's covariance before the step (F the
  // augmented linear step): exact for every filter on a linear model (the ETKF's P is its
  // ensemble's sample covariance).
  const LinearSystem s = LinearSystem::make();
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(5, 5), H = Eigen::MatrixXd::Zero(4, 5);
  F.topLeftCorner(3, 3) = s.A;
  F.topRightCorner(3, 2) = s.B;
  F.bottomRightCorner(2, 2).setIdentity();
  H.leftCols(3) = s.H;
  const auto frames = adaptiveNoiseFrames(s, 12, 1e-3);
  for (AdaptiveNoiseFilter kind :
       {AdaptiveNoiseFilter::Ukf, AdaptiveNoiseFilter::Roukf, AdaptiveNoiseFilter::Etkf}) {
    LinearModel model(s);
    SerialExecutor serial;
    const std::unique_ptr<Filter> filter = adaptiveNoiseFilter(kind, model, serial);
    for (size_t i = 0; i < frames.size(); ++i) {
      Observation y = frames[i];
      if (y.values.size() > 0) y.variance.setConstant(1e-6);
      const Eigen::MatrixXd HPH = H * F * filter->covariance() * F.transpose() * H.transpose();
      double trace = 0.0;
      for (Eigen::Index r = 0; r < 4; ++r)
        if (y.values.size() > 0 && (y.present.empty() || y.present[static_cast<size_t>(r)]))
          trace += HPH(r, r);
      const FilterStepReport report = filter->step(y);
      EXPECT_NEAR(report.predictedObservationTrace, trace, 1e-9 * std::max(trace, 1e-12))
          << adaptiveNoiseName(kind) << " step " << i;
      EXPECT_NEAR(report.innovationSquaredNorm, report.innovationNorm * report.innovationNorm,
                  1e-12 * report.innovationSquaredNorm + 1e-300);
      if (y.values.size() == 0) {
        EXPECT_EQ(report.predictedObservationTrace, 0.0);
      }
    }
  }
}

TEST(AdaptiveNoise, EstimatorIsTheMeanSquareInnovationWhenThePredictionIsSharp) {
  // t = 0: sigma^2 = sum ||nu||^2 / sum m over the window; the steps missing from a window not yet
  // full hold the initial sigma^2; a prediction-only step changes nothing; the floor holds.
  InnovationNoiseEstimator e(1.0, 4, 0.1);
  EXPECT_DOUBLE_EQ(e.sigma(), 1.0);
  e.add(3 * 4.0, 3, 0.0);  // s = 4
  EXPECT_NEAR(e.variance(), 0.25 * 4.0 + 0.75 * 1.0, 1e-12);
  e.add(123.0, 0, 5.0);
  EXPECT_EQ(e.steps(), 1);
  e.add(3 * 4.0, 3, 0.0);
  e.add(6 * 2.0, 6, 0.0);
  e.add(3 * 4.0, 3, 0.0);  // the window is full: (12 + 12 + 12 + 12) / 15
  EXPECT_NEAR(e.variance(), 48.0 / 15.0, 1e-12);
  e.add(0.0, 3, 0.0);  // the first step leaves: (12 + 12 + 12 + 0) / 15
  EXPECT_NEAR(e.variance(), 36.0 / 15.0, 1e-12);
  for (int i = 0; i < 4; ++i) e.add(0.0, 3, 0.0);
  EXPECT_DOUBLE_EQ(e.variance(), 0.1 * 0.1);  // the floor
  // A wide prediction: the trace is subtracted, and such a step counts less than a sharp one.
  InnovationNoiseEstimator wide(1.0, 2, 0.1);
  wide.add(2 * 1.0 + 100.0, 2, 100.0);  // s = 1, t / m = 50
  wide.add(2 * 9.0, 2, 0.0);            // s = 9, sharp
  EXPECT_GT(wide.variance(), 8.0);
  EXPECT_LT(wide.variance(), 9.0);
  // The likelihood equation holds at the estimate.
  const double v = wide.variance();
  const double lhs = 2 * (1.0 - v) / ((50 + v) * (50 + v)) + 2 * (9.0 - v) / (v * v);
  EXPECT_NEAR(lhs, 0.0, 1e-9);

  // A checkpoint's window restored continues exactly.
  InnovationNoiseEstimator copy(1.0, 2, 0.1);
  copy.restore(wide.saved(), wide.variance());
  wide.add(2 * 3.0, 2, 0.5);
  copy.add(2 * 3.0, 2, 0.5);
  EXPECT_EQ(copy.variance(), wide.variance());
  EXPECT_THROW(copy.restore(Eigen::MatrixXd::Ones(2, 2), 1.0), InputError);
  EXPECT_THROW(InnovationNoiseEstimator(1e-4, 0, 1e-5), InputError);
  EXPECT_THROW(InnovationNoiseEstimator(1e-4, 3, 1e-3), InputError);
}

// (a) data of sigma 2e-3, the filter assuming 1e-4 at first: once the window holds only steps
// after the first 200, within 10 % of the truth and within 3 % of the noise actually drawn in the
// window (the sample's own spread, about 1.9 % for 400 steps of 3-4 entries, is the rest).
TEST(AdaptiveNoise, EveryFilterFindsTheDataNoiseFromATwentyTimesSmallerGuess) {
  const double truth = 2e-3;
  const int steps = 1000, window = 400;
  std::vector<Eigen::Vector2d> drawn;
  const auto frames = adaptiveNoiseFrames(LinearSystem::make(), steps, truth, &drawn);
  for (AdaptiveNoiseFilter kind :
       {AdaptiveNoiseFilter::Ukf, AdaptiveNoiseFilter::Roukf, AdaptiveNoiseFilter::Etkf}) {
    InnovationNoiseEstimator noise(1e-4, window, 1e-5);
    const std::vector<double> sigmas = adaptiveNoiseRun(kind, frames, noise);
    double worst = 0.0, worstDrawn = 0.0;
    for (int i = 600; i < steps; ++i) {
      const double sigma = sigmas[static_cast<size_t>(i)];
      worst = std::max(worst, std::abs(sigma / truth - 1.0));
      worstDrawn =
          std::max(worstDrawn, std::abs(sigma / adaptiveNoiseDrawnSigma(drawn, i, window) - 1.0));
    }
    EXPECT_LT(worst, 0.10) << adaptiveNoiseName(kind);
    EXPECT_LT(worstDrawn, 0.03) << adaptiveNoiseName(kind);
    EXPECT_GT(sigmas[100], 5e-4) << adaptiveNoiseName(kind);  // on its way: 1e-4 -> 2e-3
    std::printf(
        "[ adaptive ] %s from 1e-4: sigma %.6g after 100 steps, %.6g after %d (truth %.4g); "
        "steps 600..%d: worst %.2f %% off the truth, %.2f %% off the noise drawn\n",
        adaptiveNoiseName(kind), sigmas[100], sigmas.back(), steps, truth, steps, 100 * worst,
        100 * worstDrawn);
  }
}

// (b) the filter assuming the data's sigma: the estimate stays within 10 % of it at every step.
TEST(AdaptiveNoise, EveryFilterKeepsARightGuess) {
  const double truth = 2e-3;
  const int steps = 500;
  const auto frames = adaptiveNoiseFrames(LinearSystem::make(), steps, truth);
  for (AdaptiveNoiseFilter kind :
       {AdaptiveNoiseFilter::Ukf, AdaptiveNoiseFilter::Roukf, AdaptiveNoiseFilter::Etkf}) {
    InnovationNoiseEstimator noise(truth, 200, 1e-5);
    const std::vector<double> sigmas = adaptiveNoiseRun(kind, frames, noise);
    double worst = 0.0;
    for (double sigma : sigmas) worst = std::max(worst, std::abs(sigma / truth - 1.0));
    EXPECT_LT(worst, 0.10) << adaptiveNoiseName(kind);
    std::printf("[ adaptive ] %s from the truth: sigma %.6g after %d steps, worst %.2f %%\n",
                adaptiveNoiseName(kind), sigmas.back(), steps, 100 * worst);
  }
}

// (c) noise-free data: the estimate falls to the floor and never below it.
TEST(AdaptiveNoise, TheFloorHoldsOnNoiseFreeData) {
  const double floor = 1e-5;
  const int steps = 300;
  const auto frames = adaptiveNoiseFrames(LinearSystem::make(), steps, 0.0);
  for (AdaptiveNoiseFilter kind :
       {AdaptiveNoiseFilter::Ukf, AdaptiveNoiseFilter::Roukf, AdaptiveNoiseFilter::Etkf}) {
    InnovationNoiseEstimator noise(1e-4, 30, floor);
    const std::vector<double> sigmas = adaptiveNoiseRun(kind, frames, noise);
    EXPECT_GE(*std::min_element(sigmas.begin(), sigmas.end()), floor) << adaptiveNoiseName(kind);
    EXPECT_LT(sigmas.back(), 1.05 * floor) << adaptiveNoiseName(kind);
    std::printf("[ adaptive ] %s on noise-free data: sigma %.4g after %d steps (floor %.4g)\n",
                adaptiveNoiseName(kind), sigmas.back(), steps, floor);
  }
}

}  // namespace
}  // namespace bcassim
