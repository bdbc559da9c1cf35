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
using testing::kLinearSteps;
using testing::kLinearTheta;
using testing::linearLayout;
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

// Steps `filter` and the exact KF side by side; the KF corrects with the frame the operator
// returned, and the operator was linearised at the KF's own predicted state.
void expectExactThroughOperator(Filter& filter, DroppingOperator& op, const LinearSystem& s,
                                const StochasticState& layout, double tol,
                                const std::string& name) {
  ExactKalman kf(s, layout.initialMean(),
                 layout.initialStddev().array().square().matrix().asDiagonal());
  const auto frames = testing::linearFrames(s, kLinearTheta, kLinearSteps, 0.05);
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
  const StochasticState layout = linearLayout(0.1);
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

// y = h(o) = (o0^2, o0 o1, o1^2), linearised at the mean it was given: predict(o) =
// h(m) + J(m) (o - m). Linearised again at each pass's analysed mean, one step's analysis is the
// iterated Kalman filter, whose fixed point is the maximum a posteriori estimate.
class QuadraticOperator final : public ObservationOperator {
 public:
  static Eigen::Vector3d h(const Eigen::Vector2d& o) { return testing::Quadratic::h(o); }
  static Eigen::Matrix<double, 3, 2> jacobian(const Eigen::Vector2d& o) {
    return testing::Quadratic::jacobian(o);
  }
  Observation linearize(const Eigen::VectorXd& mean, const Observation& frame) override {
    at_ = mean;
    ++linearizations;
    return frame;
  }
  void predict(const Eigen::VectorXd& o, Eigen::VectorXd& z) const override {
    z = h(at_) + jacobian(at_) * (o - at_);
  }
  int linearizations = 0;

 private:
  Eigen::Vector2d at_;
};

// The MAP of prior N(mu, diag(sd^2)) and y = h(theta) + N(0, sigma^2 I), by Gauss-Newton on its
// cost, written out here independently of the filters.
Eigen::Vector2d maximumAPosteriori(const Eigen::Vector2d& mu, const Eigen::Vector2d& sd,
                                   const Eigen::Vector3d& y, double sigma) {
  const Eigen::Matrix2d Pinv = sd.array().square().inverse().matrix().asDiagonal();
  Eigen::Vector2d theta = mu;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Matrix<double, 3, 2> J = QuadraticOperator::jacobian(theta);
    const Eigen::Matrix2d A = Pinv + J.transpose() * J / (sigma * sigma);
    const Eigen::Vector2d g =
        Pinv * (theta - mu) - J.transpose() * (y - QuadraticOperator::h(theta)) / (sigma * sigma);
    theta -= A.ldlt().solve(g);
  }
  return theta;
}

// The parameters are the observables (a static model whose whole output the operator maps).
class ParameterObservingModel final : public ForecastModel {
 public:
  Eigen::Index stateSize() const override { return 0; }
  Eigen::Index observableSize() const override { return 2; }
  void forecast(const Eigen::VectorXd&, const Eigen::VectorXd& params, Eigen::VectorXd& newState,
                Eigen::VectorXd& observable) override {
    newState.resize(0);
    observable = params;
  }
  void endStep(const Eigen::VectorXd&, const Eigen::VectorXd&) override {}
};

TEST(ObservationOperator, RelinearisedAtTheAnalysedMeanEveryFilterReachesTheMaximumAPosteriori) {
  const Eigen::Vector2d mu(1.0, -0.5), sd(0.4, 0.3);
  const StochasticState layout(Eigen::VectorXd(), Eigen::VectorXd(),
                               {{"a", mu(0), sd(0), {}}, {"b", mu(1), sd(1), {}}});
  const double sigma = 0.05;
  const Eigen::Vector3d y = QuadraticOperator::h(Eigen::Vector2d(1.5, -0.2));  // far from mu
  const Observation frame = Observation::withSigma(y, sigma);
  const Eigen::Vector2d map = maximumAPosteriori(mu, sd, y, sigma);
  ASSERT_LT((QuadraticOperator::h(map) - y).norm(), 0.05);

  // passes = 0: linearised at the prior mean only, which is not the MAP; 40 with a tolerance of
  // 1e-10 analysed standard deviations: the MAP; 40 with the default tolerance (0.1): within a
  // tenth of the analysed spread of it, in fewer passes.
  for (const auto& [passes, tolerance] :
       std::vector<std::pair<int, double>>{{0, 0.1}, {40, 1e-10}, {40, 0.1}}) {
    auto check = [&, passes = passes, tolerance = tolerance](Filter& filter, QuadraticOperator& op,
                                                             const std::string& name) {
      const FilterStepReport report = filter.step(frame);
      const Eigen::Vector2d error = filter.mean() - map;
      const double spread = std::sqrt(error.dot(filter.covariance().ldlt().solve(error)));
      const std::string label = name + " passes " + std::to_string(passes);
      EXPECT_EQ(op.linearizations, report.relinearizations + 1) << label;
      if (passes == 0) {
        EXPECT_GT(spread, 1.0) << label;
      } else if (tolerance < 1e-3) {
        EXPECT_LT(error.cwiseAbs().maxCoeff(), 1e-8) << label;
        EXPECT_LT(report.relinearizations, passes) << label << ": stopped by the tolerance";
      } else {
        EXPECT_LT(spread, 0.2) << label;
        EXPECT_LE(report.relinearizations, 10) << label;
      }
    };
    auto configure = [&, passes = passes, tolerance = tolerance](FilterOptions& o,
                                                                 QuadraticOperator& op) {
      o.observation = &op;
      o.relinearizations = passes;
      o.relinearizationTolerance = tolerance;
    };
    {
      ParameterObservingModel model;
      QuadraticOperator op;
      SerialExecutor serial;
      RoukfOptions o;
      configure(o, op);
      RoukfFilter roukf(layout, {&model}, serial, o);
      check(roukf, op, "roukf");
    }
    {
      ParameterObservingModel model;
      QuadraticOperator op;
      SerialExecutor serial;
      UkfOptions o;
      configure(o, op);
      UkfFilter ukf(layout, {&model}, serial, o);
      check(ukf, op, "ukf");
    }
    {
      // Members with the prior's exact moments: the ETKF analysis is the Kalman analysis.
      ParameterObservingModel model;
      QuadraticOperator op;
      SerialExecutor serial;
      const SigmaPointSet simplex = simplexSigmaPoints(layout.size());
      const double N = static_cast<double>(simplex.count());
      EtkfOptions o;
      configure(o, op);
      o.members = static_cast<int>(N);
      EtkfFilter etkf(layout, {&model}, serial, o);
      etkf.reset(simplex.points(layout.initialMean(),
                                std::sqrt((N - 1) / N) * sd.asDiagonal().toDenseMatrix()));
      check(etkf, op, "etkf");
    }
  }
}

// An operator that does not depend on where it is linearised (the identity): the second pass
// corrects exactly as the first, so the passes stop there, at the Kalman filter's answer.
TEST(ObservationOperator, RelinearisingALinearOperatorStopsAfterOnePassWithTheSameAnswer) {
  Eigen::MatrixXd G(3, 2);
  G << 1.0, 0.5, -0.3, 2.0, 0.7, 0.1;
  const StochasticState layout(Eigen::VectorXd(), Eigen::VectorXd(),
                               {{"a", 0.5, 0.4, {}}, {"b", 0.0, 0.3, {}}});
  const Observation frame =
      Observation::withSigma(G * Eigen::Vector2d(1.0, -0.5) + LinearStatic::offset(1), 0.05);
  for (const int passes : {0, 5}) {
    LinearStatic model(G);
    SerialExecutor serial;
    RoukfOptions o;
    o.relinearizations = passes;
    RoukfFilter roukf(layout, {&model}, serial, o);
    const FilterStepReport report = roukf.step(frame);
    EXPECT_EQ(report.relinearizations, passes == 0 ? 0 : 1);
    LinearStatic reference(G);
    RoukfFilter once(layout, {&reference}, serial, RoukfOptions{});
    once.step(frame);
    EXPECT_LT((roukf.mean() - once.mean()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((roukf.covariance() - once.covariance()).cwiseAbs().maxCoeff(), 1e-12);
  }
  LinearStatic model(G);
  SerialExecutor serial;
  RoukfOptions o;
  o.relinearizations = -1;
  EXPECT_THROW(RoukfFilter(layout, {&model}, serial, o), InputError);
}

TEST(ObservationOperator, RoukfRefusesProcessNoiseOnThePhysicalPart) {
  const LinearSystem s = LinearSystem::make();
  StateObservingModel model(s);
  SerialExecutor serial;
  RoukfOptions o;
  o.processVariance = (Eigen::VectorXd(5) << 0, 1e-3, 0, 1e-3, 0).finished();
  try {
    RoukfFilter roukf(linearLayout(0.0), {&model}, serial, o);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "reduced-order filter: process noise on the physical part would raise the rank; "
                 "give it on the parameters only");
  }
}

}  // namespace
}  // namespace bcassim
