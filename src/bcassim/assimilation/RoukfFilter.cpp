#include "bcassim/assimilation/RoukfFilter.h"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/ObservedSubset.h"

namespace bcassim {
namespace {
// S = L C^-T with U = C C^T, so that S S^T = L U^-1 L^T: the square root that samples (eq. 3.10).
Eigen::MatrixXd sqrtFactor(const Eigen::MatrixXd& L, const Eigen::MatrixXd& U, RepairLog& log) {
  const Eigen::MatrixXd C = choleskyWithRepair(U, log);
  return C.triangularView<Eigen::Lower>().solve(L.transpose()).transpose();
}
}  // namespace

RoukfFilter::RoukfFilter(StochasticState layout, std::vector<ForecastModel*> models,
                         Executor& executor, const RoukfOptions& options)
    : ensemble_(std::move(layout), std::move(models), executor, options.firstSigmaPointAlone,
                options.observation, options.distribution) {
  const StochasticState& s = ensemble_.layout();
  const Eigen::VectorXd& q = options.processVariance;
  if (q.size() != 0) {
    if (q.size() != s.size())
      throw InputError(fmt::format(
          "process noise has {} variances, the stochastic state {} entries", q.size(), s.size()));
    if (!q.head(s.physicalSize()).isZero(0.0))
      throw InputError(
          "reduced-order filter: process noise on the physical part would raise the rank; give "
          "it on the parameters only");
    if (!(q.array() >= 0.0).all() || !q.allFinite())
      throw InputError("process noise variances must be finite and >= 0");
    if (!q.isZero(0.0)) processVariance_ = q.tail(s.parameterCount());
  }
  if (options.relinearizations < 0) throw InputError("relinearizations must be >= 0");
  if (options.forecastRetries < 0) throw InputError("forecast retries must be >= 0");
  forecastRetries_ = options.forecastRetries;
  relinearizations_ = options.relinearizations;
  relinearizationTolerance_ = options.relinearizationTolerance;
  if (options.reforecasts < 0) throw InputError("reforecasts must be >= 0");
  if (!(options.reforecastBeyond > 0) || !std::isfinite(options.reforecastBeyond))
    throw InputError(
        "reforecast_beyond must be a finite number > 0 (forecast standard deviations)");
  if (options.reforecasts > 0 && s.physicalSize() != 0)
    throw InputError(
        "reforecasts: only for a state of parameters alone (static frames); this one carries "
        "the mechanical state too");
  if (options.reforecasts > 0 && options.distribution)
    throw InputError(
        "reforecasts: not with forecasts shared with other processes (--mpi): the models there "
        "cannot re-centre within a step");
  reforecasts_ = options.reforecasts;
  reforecastBeyond_ = options.reforecastBeyond;
  const Eigen::VectorXd sd = s.initialStddev();
  std::vector<Eigen::Index> reduced;
  for (Eigen::Index i = 0; i < s.size(); ++i)
    if (sd[i] > 0) reduced.push_back(i);
  const auto r = static_cast<Eigen::Index>(reduced.size());
  if (r == 0) throw InputError("reduced-order filter has nothing to estimate: every sigma is 0");
  x_ = s.initialMean();
  L_.setZero(s.size(), r);
  U_.setZero(r, r);
  for (Eigen::Index k = 0; k < r; ++k) {
    L_(reduced[k], k) = 1.0;
    U_(k, k) = 1.0 / (sd[reduced[k]] * sd[reduced[k]]);
  }
  sigma_ = makeSigmaPoints(options.sigmaPoints, r);
}

Eigen::MatrixXd RoukfFilter::covariance() const {
  const Eigen::MatrixXd S = covarianceFactor();
  return S * S.transpose();
}

Eigen::MatrixXd RoukfFilter::covarianceFactor() const {
  RepairLog ignored;
  return sqrtFactor(L_, U_, ignored);
}

void RoukfFilter::reset(Eigen::VectorXd mean, Eigen::MatrixXd L, Eigen::MatrixXd U) {
  const Eigen::Index n = ensemble_.layout().size();
  const Eigen::Index r = rank();
  if (mean.size() != n || L.rows() != n || L.cols() != r || U.rows() != r || U.cols() != r)
    throw InputError(fmt::format("ROUKF state must be: mean {}, L {}x{}, U {}x{}", n, n, r, r, r));
  x_ = std::move(mean);
  L_ = std::move(L);
  U_ = std::move(U);
}

// U^-1 += L_p^+ Q_p L_p^+T in the factored form U = (U^-1)^-1, U being the identity right after
// the prediction. L_p (parameters x r) has full row rank while the parameters' covariance is
// positive definite, so L_p L_p^+ = Id and the parameters' covariance grows by Q_p exactly.
void RoukfFilter::addParameterNoise(RepairLog& repairs) {
  if (processVariance_.size() == 0) return;
  const Eigen::Index p = processVariance_.size();
  const Eigen::MatrixXd Lp = L_.bottomRows(p);
  const Eigen::MatrixXd pinv =
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(Lp).pseudoInverse();
  Eigen::MatrixXd covariance = U_.inverse();
  covariance.noalias() += pinv * processVariance_.asDiagonal() * pinv.transpose();
  const Eigen::MatrixXd C = choleskyWithRepair(covariance, repairs);
  const Eigen::MatrixXd Cinv =
      C.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(C.rows(), C.cols()));
  U_ = Cinv.transpose() * Cinv;
}

// tr(H P H^T) = tr(HL U^-1 HL^T) with the predicted U: the identity unless parameter noise was
// added (then ||C^-1 HL^T||_F^2 with U = C C^T, repaired as every factor of U is).
double RoukfFilter::predictedTrace(const Eigen::MatrixXd& HL, RepairLog& repairs) const {
  if (processVariance_.size() == 0) return HL.squaredNorm();
  const Eigen::MatrixXd C = choleskyWithRepair(U_, repairs);
  return C.triangularView<Eigen::Lower>().solve(HL.transpose()).squaredNorm();
}

// The sigma points an analysis linearises the observations with, and where they sit against the
// forecast (mean x_f, basis L): their observables and predictions, their mean x_f + L centre,
// and H L = (H S) toForecast where H S is the regression of their predictions on their anomalies
// (the forecast's own points: L itself, toForecast the identity, centre 0).
struct RoukfFilter::Linearisation {
  Eigen::MatrixXd observables;
  Eigen::MatrixXd predicted;  // relinearised in place by correct()
  Eigen::MatrixXd toForecast;
  Eigen::VectorXd centre;
};

// Correction (Alg. 2 lines 21-27) from the forecast (x_f, L, U_f) in whitened form: with
// W = R^-1/2 H L and d = R^-1/2 (y - z(x_f)), U = U_f + W^T W and x = x_f + L U^-1 W^T d, where
// z(x_f) = z_mean - H L centre is the prediction linearised about the points' mean. The update
// is L g, so the analysed observables are the points' moved by the coefficients
// D_w I^T toForecast (g - centre): where a relinearisation linearises the operator again before
// correcting from the same forecast. Returns g (empty when nothing was in the operator's reach;
// then x_ and U_ are left as they were).
Eigen::VectorXd RoukfFilter::correct(const Observation& y, Observation used, Linearisation& at,
                                     const Eigen::VectorXd& forecastMean,
                                     const Eigen::MatrixXd& forecastU, FilterStepReport& report,
                                     RepairLog& repairs) {
  const Eigen::VectorXd& w = sigma_.weights;
  const Eigen::MatrixXd DIt = w.asDiagonal() * sigma_.unit.transpose();  // s x r
  Eigen::MatrixXd& predicted = at.predicted;
  Eigen::VectorXd gain, previousGain;
  for (int pass = 0;; ++pass) {
    const ObservedSubset obs(used, predicted.rows());
    // Nothing within the operator's reach (after a relinearisation: the last pass stands).
    if (obs.empty()) break;
    x_ = forecastMean;
    U_ = forecastU;
    const Eigen::MatrixXd Zs = obs.selectRows(predicted);
    const Eigen::VectorXd zMean = Zs * w;
    const Eigen::MatrixXd HL = (Zs.colwise() - zMean) * DIt * at.toForecast;  // H L
    const Eigen::MatrixXd W = obs.whiten(HL);
    const Eigen::VectorXd innovation = obs.values() - zMean + HL * at.centre;
    report.predictedObservationTrace = predictedTrace(HL, repairs);
    U_.noalias() += W.transpose() * W;
    const Eigen::MatrixXd C = choleskyWithRepair(U_, repairs);
    const auto Cl = C.triangularView<Eigen::Lower>();
    gain = Cl.transpose().solve(Cl.solve(W.transpose() * obs.whiten(innovation)));
    x_ += L_ * gain;
    report.innovationSquaredNorm = innovation.squaredNorm();
    report.innovationNorm = std::sqrt(report.innovationSquaredNorm);
    report.observed = obs.size();
    report.relinearizations = pass;
    if (pass == relinearizations_) break;
    // The analysed covariance is L U^-1 L^T: a move L d is d^T U d in its Mahalanobis metric.
    if (pass > 0) {
      const Eigen::VectorXd d = gain - previousGain;
      if (d.dot(U_ * d) <= relinearizationTolerance_ * relinearizationTolerance_) break;
    }
    previousGain = gain;
    used = ensemble_.predict(y, w, at.observables, predicted,
                             DIt * (at.toForecast * (gain - at.centre)));
  }
  return gain;
}

FilterStepReport RoukfFilter::step(const Observation& y) {
  const auto start = Clock::now();
  FilterStepReport report;
  RepairLog repairs;

  // Prediction (Alg. 2 lines 11-17): sample, forecast, then L = X D_w I^T. Subtracting the mean
  // first changes nothing in exact arithmetic (sum w I = 0) but avoids cancellation when the
  // state is large (positions) and the spread small.
  const Eigen::MatrixXd X = sigma_.points(x_, sqrtFactor(L_, U_, repairs));
  Eigen::MatrixXd Xf, O, Z;
  const auto forecastStart = Clock::now();
  const ForecastRetries retried =
      ensemble_.forecastRetrying(X, sigma_.weights, forecastRetries_, Xf, O);
  report.forecastHalvings = retried.halvings;
  report.forecastFailure = retried.failure;
  report.seconds.forecast = secondsSince(forecastStart);

  const auto correctionStart = Clock::now();
  const Eigen::VectorXd& w = sigma_.weights;
  const Eigen::MatrixXd DIt = w.asDiagonal() * sigma_.unit.transpose();  // s x r
  x_ = sigma_.meanOf(Xf);
  L_ = (Xf.colwise() - x_) * DIt;
  // After the prediction P = L L^T: the reduced covariance is I D_w I^T = Id.
  const Eigen::Index r = rank();
  U_.setIdentity(r, r);
  addParameterNoise(repairs);
  Observation used = ensemble_.predict(y, w, O, Z);
  const Eigen::VectorXd forecastMean = x_;
  const Eigen::MatrixXd forecastU = U_;
  Linearisation at{std::move(O), std::move(Z), Eigen::MatrixXd::Identity(r, r),
                   Eigen::VectorXd::Zero(r)};
  Eigen::VectorXd gain = correct(y, std::move(used), at, forecastMean, forecastU, report, repairs);

  // Iterated: where the analysis left the forecasts' reach, forecast again about it. The first
  // move is judged under the forecast covariance, the next ones under the analysed one.
  double reforecastSeconds = 0;
  for (int k = 0; k < reforecasts_ && gain.size() > 0; ++k) {
    const Eigen::VectorXd move = gain - at.centre;
    if (k == 0 ? move.dot(forecastU * move) <= reforecastBeyond_ * reforecastBeyond_
               : move.dot(U_ * move) <= relinearizationTolerance_ * relinearizationTolerance_)
      break;
    const auto reforecastStart = Clock::now();
    const bool worthwhile = ensemble_.recentre(x_);
    if (!worthwhile) {
      reforecastSeconds += secondsSince(reforecastStart);
      break;
    }
    // The points about the analysed mean with its covariance L U^-1 L^T = S S^T, S = L C^-T:
    // their anomalies are S I, so H L = (H S) C^T.
    const Eigen::MatrixXd C = choleskyWithRepair(U_, repairs);
    const Eigen::MatrixXd S = C.triangularView<Eigen::Lower>().solve(L_.transpose()).transpose();
    Eigen::MatrixXd Xi;
    Linearisation next{Eigen::MatrixXd(), Eigen::MatrixXd(), C.transpose(), gain};
    const ForecastRetries again =
        ensemble_.forecastRetrying(sigma_.points(x_, S), w, forecastRetries_, Xi, next.observables);
    report.forecastHalvings += again.halvings;
    if (report.forecastFailure.empty()) report.forecastFailure = again.failure;
    reforecastSeconds += secondsSince(reforecastStart);
    Observation nextUsed = ensemble_.predict(y, w, next.observables, next.predicted);
    ++report.reforecasts;
    Eigen::VectorXd nextGain =
        correct(y, std::move(nextUsed), next, forecastMean, forecastU, report, repairs);
    if (nextGain.size() == 0) break;  // nothing left in reach there: the last analysis stands
    at = std::move(next);
    gain = std::move(nextGain);
  }
  report.seconds.forecast += reforecastSeconds;
  report.seconds.correction = secondsSince(correctionStart) - reforecastSeconds;

  ensemble_.endStep(x_);
  RepairLog again;  // U was factorised (and any repair counted) above
  const Eigen::MatrixXd S = sqrtFactor(L_, U_, again);
  ensemble_.layout().toReported(x_, S.rowwise().norm(), report.mean, report.stddev);
  report.covarianceRepairs = repairs.repairs;
  report.largestJitter = repairs.largestJitter;
  report.seconds.total = secondsSince(start);
  return report;
}

FilterState RoukfFilter::saveState() const { return {{Eigen::MatrixXd(x_), L_, U_}, ""}; }

void RoukfFilter::restoreState(const FilterState& state) {
  const auto fits = [&](size_t i, Eigen::Index rows, Eigen::Index cols) {
    return i < state.matrices.size() && state.matrices[i].rows() == rows &&
           state.matrices[i].cols() == cols;
  };
  if (state.matrices.size() != 3 || !fits(0, x_.size(), 1) || !fits(1, L_.rows(), L_.cols()) ||
      !fits(2, U_.rows(), U_.cols()))
    throw std::invalid_argument("RoukfFilter::restoreState: sizes differ from this filter's");
  x_ = state.matrices[0].col(0);
  L_ = state.matrices[1];
  U_ = state.matrices[2];
}

}  // namespace bcassim
