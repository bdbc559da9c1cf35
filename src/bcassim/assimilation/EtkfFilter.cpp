#include "bcassim/assimilation/EtkfFilter.h"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/ObservedSubset.h"

namespace bcassim {
namespace {
Eigen::MatrixXd standardNormal(Eigen::Index rows, Eigen::Index cols, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd out(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) out(i, j) = normal(rng);
  return out;
}
}  // namespace

EtkfFilter::EtkfFilter(StochasticState layout, std::vector<ForecastModel*> models,
                       Executor& executor, EtkfOptions options)
    : ensemble_(std::move(layout), std::move(models), executor, options.firstSigmaPointAlone,
                options.observation, options.distribution),
      options_(std::move(options)),
      rng_(options_.seed) {
  const StochasticState& s = ensemble_.layout();
  if (options_.relinearizations < 0) throw InputError("relinearizations must be >= 0");
  if (options_.forecastRetries < 0) throw InputError("forecast retries must be >= 0");
  if (options_.members < 2)
    throw InputError(fmt::format("ETKF needs at least 2 members, got {}", options_.members));
  if (options_.processVariance.size() != 0 && options_.processVariance.size() != s.size())
    throw InputError(fmt::format("process noise has {} variances, the stochastic state {} entries",
                                 options_.processVariance.size(), s.size()));
  x_ = s.initialMean();
  members_ = s.initialStddev().asDiagonal() * standardNormal(s.size(), options_.members, rng_);
  members_.colwise() += x_;
}

Eigen::MatrixXd EtkfFilter::covariance() const {
  const Eigen::MatrixXd S = covarianceFactor();
  return S * S.transpose();
}

Eigen::MatrixXd EtkfFilter::covarianceFactor() const {
  const Eigen::MatrixXd D = members_.colwise() - members_.rowwise().mean();
  return D / std::sqrt(static_cast<double>(members_.cols() - 1));
}

void EtkfFilter::reset(Eigen::MatrixXd members) {
  if (members.rows() != ensemble_.layout().size() || members.cols() < 2)
    throw InputError(
        fmt::format("ETKF ensemble must be {} x N with N >= 2", ensemble_.layout().size()));
  members_ = std::move(members);
  x_ = members_.rowwise().mean();
}

FilterStepReport EtkfFilter::step(const Observation& y) {
  const auto start = Clock::now();
  FilterStepReport report;
  const Eigen::Index N = members_.cols();
  const double nm1 = static_cast<double>(N - 1);

  // The draws are centred over the members: inflation widens the ensemble, never moves its mean.
  auto inflation = [&] {
    Eigen::MatrixXd noise = options_.processVariance.cwiseSqrt().asDiagonal() *
                            standardNormal(members_.rows(), N, rng_);
    noise.colwise() -= noise.rowwise().mean();
    return noise;
  };
  const bool inflate = options_.processVariance.size() != 0;
  // Parameters only (static frames): the observations of this step depend on the parameters
  // directly, so the members are inflated before they are forecast, as the Kalman filter's
  // P + Q comes before its prediction; otherwise after the forecast (Alg. 3 line 18).
  const bool inflateFirst = inflate && ensemble_.layout().physicalSize() == 0;
  if (inflateFirst) members_ += inflation();

  // Prediction (Alg. 3 lines 13-20).
  Eigen::MatrixXd Xf, O, Z;
  const auto forecastStart = Clock::now();
  const Eigen::VectorXd equal = Eigen::VectorXd::Constant(N, 1.0 / static_cast<double>(N));
  const ForecastRetries retried =
      ensemble_.forecastRetrying(members_, equal, options_.forecastRetries, Xf, O);
  report.forecastHalvings = retried.halvings;
  report.forecastFailure = retried.failure;
  report.seconds.forecast = secondsSince(forecastStart);

  const auto correctionStart = Clock::now();
  x_ = Xf.rowwise().mean();
  Eigen::MatrixXd Xp = Xf.colwise() - x_;
  if (inflate && !inflateFirst) Xp += inflation();
  Observation used = ensemble_.predict(y, equal, O, Z);
  members_ = Xp.colwise() + x_;

  // Correction (Alg. 3 lines 24-36, eq. 3.17-3.18). With Zt = R^-1/2 Z' = U S V^T (thin),
  // A = [(N-1) I + Zt^T Zt]^-1 = (I - V diag(s^2/(N-1+s^2)) V^T) / (N-1) and its symmetric root
  // sqrt((N-1) A) = I + V diag(sqrt((N-1)/(N-1+s^2)) - 1) V^T: O(N r^2), never an N x N solve.
  // The update X' omega moves the observables by O' omega: where a relinearisation
  // (FilterOptions) linearises the operator again before correcting from the same forecast.
  const Eigen::VectorXd forecastMean = x_;
  Eigen::VectorXd previousOmega;
  for (int pass = 0;; ++pass) {
    const ObservedSubset obs(used, Z.rows());
    if (obs.empty()) break;  // after a relinearisation: the last pass stands
    const Eigen::MatrixXd Zs = obs.selectRows(Z);
    const Eigen::VectorXd zMean = Zs.rowwise().mean();
    const Eigen::MatrixXd dZ = Zs.colwise() - zMean;
    const Eigen::MatrixXd Zt = obs.whiten(dZ);
    const Eigen::VectorXd innovation = obs.values() - zMean;
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(Zt, Eigen::ComputeThinV);
    const Eigen::MatrixXd& V = svd.matrixV();
    const Eigen::ArrayXd s2 = svd.singularValues().array().square();

    const Eigen::VectorXd b = Zt.transpose() * obs.whiten(innovation);
    const Eigen::VectorXd omega =
        (b - V * (s2 / (nm1 + s2)).matrix().asDiagonal() * (V.transpose() * b)) / nm1;
    x_ = forecastMean + Xp * omega;
    const Eigen::VectorXd shrink = ((nm1 / (nm1 + s2)).sqrt() - 1.0).matrix();
    const Eigen::MatrixXd XpV = Xp * V;
    members_ = Xp + XpV * shrink.asDiagonal() * V.transpose();
    members_.colwise() += x_;
    report.innovationSquaredNorm = innovation.squaredNorm();
    report.innovationNorm = std::sqrt(report.innovationSquaredNorm);
    report.predictedObservationTrace = dZ.squaredNorm() / nm1;  // tr(Z' Z'^T) / (N - 1)
    report.observed = obs.size();
    report.relinearizations = pass;
    if (pass == options_.relinearizations) break;
    // The analysed covariance is X' A X'^T: a move X' d is d^T A^-1 d = d^T ((N-1) I + Zt^T Zt) d
    // in its Mahalanobis metric.
    if (pass > 0) {
      const Eigen::VectorXd d = omega - previousOmega;
      const double distance2 = nm1 * d.squaredNorm() + (Zt * d).squaredNorm();
      if (distance2 <= options_.relinearizationTolerance * options_.relinearizationTolerance) break;
    }
    previousOmega = omega;
    used = ensemble_.predict(y, equal, O, Z, omega);
  }
  report.seconds.correction = secondsSince(correctionStart);

  ensemble_.endStep(x_);
  const Eigen::VectorXd sd = ((members_.colwise() - x_).rowwise().squaredNorm() / nm1).cwiseSqrt();
  ensemble_.layout().toReported(x_, sd, report.mean, report.stddev);
  report.seconds.total = secondsSince(start);
  return report;
}

FilterState EtkfFilter::saveState() const {
  std::ostringstream rng;
  rng << rng_;
  return {{Eigen::MatrixXd(x_), members_}, rng.str()};
}

void EtkfFilter::restoreState(const FilterState& state) {
  const auto fits = [&](size_t i, Eigen::Index rows, Eigen::Index cols) {
    return i < state.matrices.size() && state.matrices[i].rows() == rows &&
           state.matrices[i].cols() == cols;
  };
  if (state.matrices.size() != 2 || !fits(0, x_.size(), 1) ||
      !fits(1, members_.rows(), members_.cols()))
    throw std::invalid_argument("EtkfFilter::restoreState: sizes differ from this filter's");
  std::istringstream rng(state.text);
  std::mt19937_64 restored;
  rng >> restored;
  if (!rng) throw std::invalid_argument("EtkfFilter::restoreState: unreadable generator state");
  rng_ = restored;
  x_ = state.matrices[0].col(0);
  members_ = state.matrices[1];
}

}  // namespace bcassim
