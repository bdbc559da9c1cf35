// The observation-operator path (ObservationOperator.h): an operator linearised at the forecast
// mean, which drops entries by what it sees there, still gives every filter the exact Kalman
// posterior on a linear-Gaussian model; parameter process noise (a random walk) is the Kalman
// filter's P + Q in the ROUKF's reduced space as in the UKF.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/ObservationOperator.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/SimplexSigmaPoints.h"
#include "bcassim/assimilation/UkfFilter.h"

namespace bcassim {
namespace {
using testing::ExactKalman;
using testing::LinearSystem;

// The linear model whose observable is the state itself: H lives in the operator.
class StateObservingModel final : public ForecastModel {
 public:
  explicit StateObservingModel(const LinearSystem& s) : s_(s) {}
  Eigen::Index stateSize() const override { return s_.A.rows(); }
  Eigen::Index observableSize() const override { return s_.A.rows(); }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& observable) override {
    newState = s_.A * state + s_.B * params + s_.forcing(step_);
    observable = newState;
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override { ++step_; }

 private:
  const LinearSystem& s_;
  int step_ = 0;
};

// z = H x, and at each step the entry farthest from the mean's prediction is left out (as a
// point cloud leaves out points far from the mean's surface). Records the mean it was given and
// the frame it returned.
class DroppingOperator final : public ObservationOperator {
 public:
  explicit DroppingOperator(const Eigen::MatrixXd& H) : H_(H) {}
  Observation linearize(const Eigen::VectorXd& mean, const Observation& frame) override {
    lastMean = mean;
    used = frame;
    if (used.present.empty()) used.present.assign(static_cast<size_t>(frame.values.size()), true);
    const Eigen::VectorXd z = H_ * mean;
    Eigen::Index worst = -1;
    double largest = -1;
    for (Eigen::Index i = 0; i < z.size(); ++i)
      if (used.present[static_cast<size_t>(i)] && std::abs(frame.values(i) - z(i)) > largest) {
        largest = std::abs(frame.values(i) - z(i));
        worst = i;
      }
    if (worst >= 0) used.present[static_cast<size_t>(worst)] = false;
    return used;
  }
  void predict(const Eigen::VectorXd& x, Eigen::VectorXd& z) const override { z = H_ * x; }

  Eigen::VectorXd lastMean;
  Observation used;

 private:
  Eigen::MatrixXd H_;
};

constexpr int kLinearSteps = 8;
const Eigen::Vector2d kLinearThetaTrue(1.0, -0.5);

StochasticState linearStateLayout(double physicalSigma) {
  return StochasticState(Eigen::Vector3d(0.2, -0.1, 0.0), Eigen::Vector3d::Constant(physicalSigma),
                         {{"a", 0.5, 0.4, {}}, {"b", 0.0, 0.3, {}}});
}

// Steps `filter` and the exact KF side by side; the KF corrects with the frame the operator
// returned, and the operator was linearised at the KF's own predicted state.
void expectExactThroughOperator(Filter& filter, DroppingOperator& op, const LinearSystem& s,
                                const StochasticState& layout, double tol,
                                const std::string& name) {
  ExactKalman kf(s, layout.initialMean(),
                 layout.initialStddev().array().square().matrix().asDiagonal());
  const auto frames = testing::linearFrames(s, kLinearThetaTrue, kLinearSteps, 0.05);
  for (size_t i = 0; i < frames.size(); ++i) {
    const FilterStepReport report = filter.step(frames[i]);
    const bool data = frames[i].values.size() > 0;
    ExactKalman predicted = kf;
    predicted.step(Observation::none());
    if (data) {
      EXPECT_LT((op.lastMean - predicted.mean().head(3)).cwiseAbs().maxCoeff(), tol)
          << name << " step " << i;
    }
    kf.step(data ? op.used : frames[i]);
    EXPECT_LT((filter.mean() - kf.mean()).cwiseAbs().maxCoeff(), tol) << name << " step " << i;
    EXPECT_LT((filter.covariance() - kf.covariance()).cwiseAbs().maxCoeff(), tol)
        << name << " step " << i;
    // One entry fewer than the frame holds: 4 (3 in frame 3, which misses two), none in frame 5.
    EXPECT_EQ(report.observed, i == 3 ? 1 : i == 5 ? 0 : 3) << name << " step " << i;
  }
}

TEST(ObservationOperator, LinearisedAtTheForecastMeanEveryFilterIsTheExactKalmanFilter) {
  const LinearSystem s = LinearSystem::make();
  const StochasticState layout = linearStateLayout(0.1);
  {
    StateObservingModel model(s);
    DroppingOperator op(s.H);
    SerialExecutor serial;
    UkfOptions o;
    o.observation = &op;
    UkfFilter ukf(layout, {&model}, serial, o);
    expectExactThroughOperator(ukf, op, s, layout, 1e-9, "ukf");
  }
  {
    StateObservingModel model(s);
    DroppingOperator op(s.H);
    SerialExecutor serial;
    RoukfOptions o;
    o.observation = &op;
    RoukfFilter roukf(layout, {&model}, serial, o);
    expectExactThroughOperator(roukf, op, s, layout, 1e-9, "roukf");
  }
  {
    // Members with the prior's exact moments: the ETKF analysis is the Kalman analysis.
    StateObservingModel model(s);
    DroppingOperator op(s.H);
    SerialExecutor serial;
    const SigmaPointSet simplex = simplexSigmaPoints(layout.size());
    const double N = static_cast<double>(simplex.count());
    EtkfOptions o;
    o.observation = &op;
    o.members = static_cast<int>(N);
    EtkfFilter etkf(layout, {&model}, serial, o);
    etkf.reset(simplex.points(
        layout.initialMean(),
        std::sqrt((N - 1) / N) * layout.initialStddev().asDiagonal().toDenseMatrix()));
    expectExactThroughOperator(etkf, op, s, layout, 1e-9, "etkf");
  }
}

// z = G theta + c(step): no physical state at all, as a static model estimating forces.
class LinearStatic final : public ForecastModel {
 public:
  explicit LinearStatic(Eigen::MatrixXd G) : G_(std::move(G)) {}
  static Eigen::Vector3d offset(int step) { return Eigen::Vector3d(0.1, -0.2, 0.3) * step; }
  Eigen::Index stateSize() const override { return 0; }
  Eigen::Index observableSize() const override { return G_.rows(); }
  void forecast(const Eigen::VectorXd&, const Eigen::VectorXd& params, Eigen::VectorXd& newState,
                Eigen::VectorXd& observable) override {
    newState.resize(0);
    observable = G_ * params + offset(step_ + 1);
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override { ++step_; }

 private:
  Eigen::MatrixXd G_;
  int step_ = 0;
};

TEST(ObservationOperator, ParameterRandomWalkIsTheKalmanFilterWithProcessNoise) {
  Eigen::MatrixXd G(3, 2);
  G << 1.0, 0.5, -0.3, 2.0, 0.7, 0.1;
  const Eigen::Vector2d q(0.04, 0.01);
  const StochasticState layout(Eigen::VectorXd(), Eigen::VectorXd(),
                               {{"a", 0.5, 0.4, {}}, {"b", 0.0, 0.3, {}}});
  const double sigma = 0.05;
  // A drifting truth, so that the noise matters.
  std::vector<Observation> frames;
  for (int k = 1; k <= kLinearSteps; ++k) {
    const Eigen::Vector2d theta(1.0 + 0.2 * k, -0.5 + 0.1 * k);
    frames.push_back(Observation::withSigma(G * theta + LinearStatic::offset(k), sigma));
  }
  frames[4] = Observation::none();
  auto runExact = [&](std::vector<Eigen::VectorXd>& means, std::vector<Eigen::MatrixXd>& covs) {
    Eigen::VectorXd m = layout.initialMean();
    Eigen::MatrixXd P = layout.initialStddev().array().square().matrix().asDiagonal();
    for (int k = 1; k <= kLinearSteps; ++k) {
      P.diagonal() += q;
      const Observation& y = frames[static_cast<size_t>(k - 1)];
      if (y.values.size() > 0) {
        const Eigen::MatrixXd S =
            G * P * G.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(3, 3);
        const Eigen::MatrixXd K = P * G.transpose() * S.inverse();
        m += K * (y.values - G * m - LinearStatic::offset(k));
        P -= K * S * K.transpose();
      }
      means.push_back(m);
      covs.push_back(P);
    }
  };
  std::vector<Eigen::VectorXd> means;
  std::vector<Eigen::MatrixXd> covs;
  runExact(means, covs);
  const Eigen::VectorXd process = q;

  auto check = [&](Filter& filter, const std::string& name) {
    for (int k = 0; k < kLinearSteps; ++k) {
      filter.step(frames[static_cast<size_t>(k)]);
      EXPECT_LT((filter.mean() - means[static_cast<size_t>(k)]).cwiseAbs().maxCoeff(), 1e-10)
          << name << " step " << k + 1;
      EXPECT_LT((filter.covariance() - covs[static_cast<size_t>(k)]).cwiseAbs().maxCoeff(), 1e-10)
          << name << " step " << k + 1;
    }
  };
  {
    LinearStatic model(G);
    SerialExecutor serial;
    RoukfOptions o;
    o.processVariance = process;
    RoukfFilter roukf(layout, {&model}, serial, o);
    check(roukf, "roukf");
  }
  {
    LinearStatic model(G);
    SerialExecutor serial;
    UkfOptions o;
    o.sigmaPoints = SigmaPointKind::Simplex;
    o.processVariance = process;
    UkfFilter ukf(layout, {&model}, serial, o);
    check(ukf, "ukf");
  }
}

TEST(ObservationOperator, RoukfRefusesProcessNoiseOnThePhysicalPart) {
  const LinearSystem s = LinearSystem::make();
  StateObservingModel model(s);
  SerialExecutor serial;
  RoukfOptions o;
  o.processVariance = (Eigen::VectorXd(5) << 0, 1e-3, 0, 1e-3, 0).finished();
  try {
    RoukfFilter roukf(linearStateLayout(0.0), {&model}, serial, o);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "reduced-order filter: process noise on the physical part would raise the rank; "
                 "give it on the parameters only");
  }
}

}  // namespace
}  // namespace bcassim
