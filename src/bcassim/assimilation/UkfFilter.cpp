#include "bcassim/assimilation/UkfFilter.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/LocalUkfCovariance.h"
#include "bcassim/assimilation/ObservedSubset.h"
#include "bcassim/assimilation/StarSigmaPoints.h"

namespace bcassim {
UkfFilter::UkfFilter(StochasticState layout, std::vector<ForecastModel*> models, Executor& executor,
                     UkfOptions options)
    : ensemble_(std::move(layout), std::move(models), executor, options.firstSigmaPointAlone,
                options.observation, options.distribution),
      options_(std::move(options)) {
  const StochasticState& s = ensemble_.layout();
  if (options_.relinearizations < 0) throw InputError("relinearizations must be >= 0");
  const Eigen::Index n = s.size();
  if (options_.forecastRetries < 0) throw InputError("forecast retries must be >= 0");
  if (!(options_.spread > 0.0) || !std::isfinite(options_.spread))
    throw InputError(
        fmt::format("UKF sigma-point spread must be positive, got {}", options_.spread));
  if (options_.processVariance.size() != 0 && options_.processVariance.size() != n)
    throw InputError(fmt::format("process noise has {} variances, the stochastic state {} entries",
                                 options_.processVariance.size(), n));
  sigma_ = options_.sigmaPoints == SigmaPointKind::Star ? starSigmaPoints(n, options_.starKappa)
                                                        : makeSigmaPoints(options_.sigmaPoints, n);
  if (options_.distribution != nullptr) P_ = options_.distribution->ukfCovariance(sigma_);
  if (!P_) P_ = std::make_unique<LocalUkfCovariance>();
  x_ = s.initialMean();
  P_->assign(s.initialStddev().array().square().matrix().asDiagonal());
}

void UkfFilter::reset(Eigen::VectorXd mean, const Eigen::MatrixXd& covariance) {
  const Eigen::Index n = ensemble_.layout().size();
  if (mean.size() != n || covariance.rows() != n || covariance.cols() != n)
    throw InputError(fmt::format("UKF state must have {} entries and a {}x{} covariance", n, n, n));
  x_ = std::move(mean);
  P_->assign(covariance);
}

Eigen::MatrixXd UkfFilter::covarianceFactor() const {
  RepairLog ignored;
  return choleskyWithRepair(P_->matrix(), ignored);
}

FilterStepReport UkfFilter::step(const Observation& y) {
  const auto start = Clock::now();
  FilterStepReport report;
  RepairLog repairs;

  // Parameters only (static frames): the step's observations depend on the parameters directly,
  // so Q enters before the sigma points are drawn, as in the Kalman filter's P + Q (with F = Id).
  const bool noiseFirst =
      options_.processVariance.size() != 0 && ensemble_.layout().physicalSize() == 0;
  if (noiseFirst) P_->addToDiagonal(options_.processVariance);

  // Prediction (Alg. 1 lines 9-14).
  Eigen::MatrixXd O, Z;
  const auto forecastStart = Clock::now();
  // A failed forecast is redone with the points closer to the mean (FilterOptions::
  // forecastRetries): the scaled transform's spread reduced, its deviations divided by it.
  const ForecastRetries retried = retryCloserToTheMean(options_.forecastRetries, [&](double k) {
    P_->forecast(ensemble_, sigma_, x_, options_.spread * k, O, repairs);
  });
  report.forecastHalvings = retried.halvings;
  report.forecastFailure = retried.failure;
  const double spread = options_.spread * retried.spread;
  report.seconds.forecast = secondsSince(forecastStart);

  const auto correctionStart = Clock::now();
  const Eigen::VectorXd& w = sigma_.weights;
  const double unscale = 1.0 / spread;
  P_->moments(sigma_, spread, x_);
  if (options_.processVariance.size() != 0 && !noiseFirst)
    P_->addToDiagonal(options_.processVariance);
  Observation used = ensemble_.predict(y, w, O, Z);

  // Correction (Alg. 1 lines 17-24) with the present entries only. The update K nu = Pxz Pz^-1 nu
  // is the combination (X_f - x) c with c = w o (dZ^T Pz^-1 nu) / spread, so the analysed
  // observables are the forecasts' moved by c: where a relinearisation (FilterOptions) linearises
  // the operator again before correcting from the same forecast.
  const int passes = options_.relinearizations;
  const Eigen::VectorXd forecastMean = x_;
  if (passes > 0) P_->keep();
  Eigen::VectorXd previousMean;
  for (int pass = 0;; ++pass) {
    const ObservedSubset obs(used, Z.rows());
    if (obs.empty()) break;  // after a relinearisation: the last pass stands
    if (pass > 0) {
      x_ = forecastMean;
      P_->restore();
    }
    const Eigen::MatrixXd Zs = obs.selectRows(Z);
    const Eigen::VectorXd zMean = Zs * w;
    const Eigen::MatrixXd dZ = unscale * (Zs.colwise() - zMean);
    const Eigen::MatrixXd Pz = dZ * w.asDiagonal() * dZ.transpose() + obs.covariance();
    const Eigen::VectorXd innovation = obs.values() - zMean;
    // With Pz = C C^T and G = C^-1 Pxz^T: K nu = G^T C^-1 nu and K Pxz^T = G^T G, which keeps the
    // corrected covariance symmetric by construction.
    const Eigen::MatrixXd C = choleskyWithRepair(Pz, repairs);
    const auto Cl = C.triangularView<Eigen::Lower>();
    const Eigen::MatrixXd G = P_->correct(w.asDiagonal() * dZ.transpose(), C);
    const Eigen::VectorXd whitened = Cl.solve(innovation);
    x_ += G.transpose() * whitened;
    report.innovationSquaredNorm = innovation.squaredNorm();
    report.innovationNorm = std::sqrt(report.innovationSquaredNorm);
    report.predictedObservationTrace = dZ.colwise().squaredNorm().transpose().dot(w);  // tr(Pz - R)
    report.observed = obs.size();
    report.relinearizations = pass;
    if (pass == passes) break;
    // The move of this pass in the Mahalanobis metric of the analysed covariance P.
    if (pass > 0) {
      RepairLog ignored;
      const Eigen::MatrixXd Pc = choleskyWithRepair(P_->matrix(), ignored);
      const double distance2 =
          Pc.triangularView<Eigen::Lower>().solve(x_ - previousMean).squaredNorm();
      if (distance2 <= options_.relinearizationTolerance * options_.relinearizationTolerance) break;
    }
    previousMean = x_;
    used = ensemble_.predict(
        y, w, O, Z, unscale * w.cwiseProduct(dZ.transpose() * Cl.transpose().solve(whitened)));
  }
  report.seconds.correction = secondsSince(correctionStart);

  // Before endStep: P kept over processes answers at once, not after their models' end of step.
  const Eigen::VectorXd variance = P_->diagonal();
  ensemble_.endStep(x_);
  ensemble_.layout().toReported(x_, variance.cwiseMax(0.0).cwiseSqrt(), report.mean, report.stddev);
  report.covarianceRepairs = repairs.repairs;
  report.largestJitter = repairs.largestJitter;
  report.seconds.total = secondsSince(start);
  return report;
}

FilterState UkfFilter::saveState() const { return {{Eigen::MatrixXd(x_), P_->matrix()}, ""}; }

void UkfFilter::restoreState(const FilterState& state) {
  const auto fits = [&](size_t i, Eigen::Index rows, Eigen::Index cols) {
    return i < state.matrices.size() && state.matrices[i].rows() == rows &&
           state.matrices[i].cols() == cols;
  };
  const Eigen::Index n = x_.size();
  if (state.matrices.size() != 2 || !fits(0, n, 1) || !fits(1, n, n))
    throw std::invalid_argument("UkfFilter::restoreState: sizes differ from this filter's");
  x_ = state.matrices[0].col(0);
  P_->assign(state.matrices[1]);
}

}  // namespace bcassim
