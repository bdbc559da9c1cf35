// On a linear-Gaussian model the UKF (every sigma-point set) and the ROUKF are the exact Kalman
// filter; the ETKF is exact for an ensemble with the prior's moments and converges to it as the
// ensemble grows. Frames with missing entries and empty frames are part of every run.
#include <gtest/gtest.h>

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

// Runs filter and exact KF side by side and checks mean and covariance after every step.
void expectExact(Filter& filter, ExactKalman& kf, const std::vector<Observation>& frames,
                 double tol, const std::string& name) {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const FilterStepReport report = filter.step(frames[i]);
    kf.step(frames[i]);
    EXPECT_LT((filter.mean() - kf.mean()).cwiseAbs().maxCoeff(), tol) << name << " step " << i;
    EXPECT_LT((filter.covariance() - kf.covariance()).cwiseAbs().maxCoeff(), tol)
        << name << " step " << i;
    EXPECT_EQ(report.observed, i == 3 ? 2 : i == 5 ? 0 : 4) << name;
    EXPECT_EQ(report.covarianceRepairs, 0) << name;
  }
}

TEST(LinearGaussian, UkfWithEverySigmaPointSetIsTheExactKalmanFilter) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
  struct Case {
    const char* name;
    SigmaPointKind kind;
    double kappa;
    double spread;
  };
  for (const Case& c : {Case{"star", SigmaPointKind::Star, 0.0, 1.0},
                        Case{"star kappa 1", SigmaPointKind::Star, 1.0, 1.0},
                        Case{"canonical", SigmaPointKind::Canonical, 0.0, 1.0},
                        Case{"simplex", SigmaPointKind::Simplex, 0.0, 1.0},
                        // the scaled transform is exact for a linear model whatever its spread
                        Case{"simplex spread 0.05", SigmaPointKind::Simplex, 0.0, 0.05},
                        Case{"star spread 3", SigmaPointKind::Star, 0.0, 3.0}}) {
    LinearModel model(s);
    SerialExecutor serial;
    UkfOptions options;
    options.sigmaPoints = c.kind;
    options.starKappa = c.kappa;
    options.spread = c.spread;
    const StochasticState layout = linearLayout(0.1);
    UkfFilter ukf(layout, {&model}, serial, options);
    ExactKalman kf = exactFor(s, layout);
    expectExact(ukf, kf, frames, 1e-9, c.name);
  }
}

TEST(LinearGaussian, UkfWithProcessNoiseOnParametersIsTheExactKalmanFilter) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
  LinearModel model(s);
  SerialExecutor serial;
  UkfOptions options;
  options.sigmaPoints = SigmaPointKind::Simplex;
  options.processVariance = (Eigen::VectorXd(5) << 0, 0, 0, 1e-3, 4e-3).finished();
  const StochasticState layout = linearLayout(0.1);
  UkfFilter ukf(layout, {&model}, serial, options);
  ExactKalman kf = exactFor(s, layout, options.processVariance);
  expectExact(ukf, kf, frames, 1e-9, "ukf with Q");
}

TEST(LinearGaussian, RoukfIsTheExactKalmanFilterAtFullAndReducedRank) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
  // Uncertain physical part: rank 5 = the whole state. Known physical part: rank 2 = parameters,
  // and the exact filter's covariance has that rank too.
  for (double physicalSigma : {0.1, 0.0}) {
    for (SigmaPointKind kind : {SigmaPointKind::Simplex, SigmaPointKind::Canonical}) {
      LinearModel model(s);
      SerialExecutor serial;
      RoukfOptions options;
      options.sigmaPoints = kind;
      const StochasticState layout = linearLayout(physicalSigma);
      RoukfFilter roukf(layout, {&model}, serial, options);
      EXPECT_EQ(roukf.rank(), physicalSigma > 0 ? 5 : 2);
      ExactKalman kf = exactFor(s, layout);
      expectExact(roukf, kf, frames, 1e-9,
                  "roukf sigma=" + std::to_string(physicalSigma) +
                      (kind == SigmaPointKind::Simplex ? " simplex" : " canonical"));
    }
  }
}

// Members whose sample mean and covariance equal the prior exactly: the ETKF analysis is then the
// Kalman analysis, step after step (it is a square-root filter, not a Monte Carlo estimate).
TEST(LinearGaussian, EtkfWithExactPriorMomentsIsTheExactKalmanFilter) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
  const StochasticState layout = linearLayout(0.1);
  const SigmaPointSet simplex = simplexSigmaPoints(layout.size());
  const double N = static_cast<double>(simplex.count());
  // Simplex points have sum w I I^T = Id with w = 1/N; the sample covariance divides by N - 1.
  const Eigen::MatrixXd members =
      simplex.points(layout.initialMean(),
                     std::sqrt((N - 1) / N) * layout.initialStddev().asDiagonal().toDenseMatrix());
  LinearModel model(s);
  SerialExecutor serial;
  EtkfOptions options;
  options.members = static_cast<int>(N);
  EtkfFilter etkf(layout, {&model}, serial, options);
  etkf.reset(members);
  ExactKalman kf = exactFor(s, layout);
  expectExact(etkf, kf, frames, 1e-9, "etkf");
}

TEST(LinearGaussian, EtkfConvergesToTheKalmanFilterAsTheEnsembleGrows) {
  const LinearSystem s = LinearSystem::make();
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
  const StochasticState layout = linearLayout(0.1);
  ExactKalman kf = exactFor(s, layout);
  for (const Observation& y : frames) kf.step(y);

  std::vector<double> error;
  for (int members : {10, 100, 1000}) {
    double sum = 0;
    for (std::uint64_t seed : {1, 2, 3, 4}) {
      LinearModel model(s);
      SerialExecutor serial;
      EtkfOptions options;
      options.members = members;
      options.seed = seed;
      EtkfFilter etkf(layout, {&model}, serial, options);
      for (const Observation& y : frames) etkf.step(y);
      // Mean error in units of the posterior spread, plus relative covariance error.
      sum += (etkf.mean() - kf.mean()).norm() / std::sqrt(kf.covariance().trace()) +
             (etkf.covariance() - kf.covariance()).norm() / kf.covariance().norm();
    }
    error.push_back(sum / 4);
  }
  EXPECT_LT(error[1], 0.6 * error[0]);
  EXPECT_LT(error[2], 0.6 * error[1]);
  EXPECT_LT(error[2], 0.1) << error[0] << " " << error[1] << " " << error[2];
}

TEST(LinearGaussian, PredictOnlyKeepsOrGrowsTheCovarianceAsTheoryStates) {
  // Parameters are constant: without data their covariance must stay exactly as it is (ROUKF) or
  // grow by exactly Q (UKF).
  testing::StaticSpring spring;
  SerialExecutor serial;
  const StochasticState layout({}, {}, {{"k", 2.0, 0.5, ParameterTransform::exponential()}});
  RoukfFilter roukf(layout, {&spring}, serial);
  const Eigen::MatrixXd P0 = roukf.covariance();
  const Eigen::VectorXd x0 = roukf.mean();
  for (int i = 0; i < 5; ++i) {
    const FilterStepReport r = roukf.step(Observation::none());
    EXPECT_EQ(r.observed, 0);
    EXPECT_EQ(r.innovationNorm, 0.0);
  }
  EXPECT_NEAR(roukf.covariance()(0, 0), P0(0, 0), 1e-14);
  EXPECT_NEAR(roukf.mean()[0], x0[0], 1e-14);

  testing::StaticSpring spring2;
  UkfOptions options;
  options.processVariance = Eigen::VectorXd::Constant(1, 0.01);
  UkfFilter ukf(layout, {&spring2}, serial, options);
  for (int i = 0; i < 5; ++i) ukf.step(Observation::none());
  EXPECT_NEAR(ukf.covariance()(0, 0), P0(0, 0) + 5 * 0.01, 1e-14);
}

TEST(LinearGaussian, BadFramesAreInputErrors) {
  const LinearSystem s = LinearSystem::make();
  LinearModel model(s);
  SerialExecutor serial;
  UkfFilter ukf(linearLayout(0.1), {&model}, serial);
  Observation nan = Observation::withSigma(Eigen::Vector4d(1, 2, std::nan(""), 4), 0.1);
  EXPECT_THROW(ukf.step(nan), InputError);
  EXPECT_THROW(ukf.step(Observation::withSigma(Eigen::Vector3d(1, 2, 3), 0.1)), InputError);
  Observation zeroNoise = Observation::withSigma(Eigen::Vector4d(1, 2, 3, 4), 0.0);
  EXPECT_THROW(ukf.step(zeroNoise), InputError);
  Observation full = Observation::withSigma(Eigen::Vector4d(1, 2, 3, 4), 0.1);
  full.covariance = 0.01 * Eigen::MatrixXd::Identity(4, 4);
  EXPECT_NO_THROW(ukf.step(full));
}

}  // namespace
}  // namespace bcassim
