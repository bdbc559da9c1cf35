#include "bcassim/distributed/MpiUkfCovariance.h"

#include <exception>
#include <stdexcept>

#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/ForecastEnsemble.h"

namespace bcassim {

namespace proto = mpi_protocol;

// The workers' kUkfSetUp, sent before the share's collective construction.
SigmaPointColumns MpiUkfCovariance::announce(MpiForecastDistribution& distribution,
                                             const SigmaPointSet& sigma) {
  SigmaPointColumns columns = compactColumns(sigma);
  const Eigen::VectorXd packed = packSigmaPoints(columns, sigma.weights);
  distribution.tellWorkers(proto::kUkfSetUp, static_cast<int>(sigma.unit.rows()),
                           static_cast<int>(packed.size()), packed);
  return columns;
}

MpiUkfCovariance::MpiUkfCovariance(MpiForecastDistribution& distribution,
                                   const SigmaPointSet& sigma)
    : distribution_(distribution),
      n_(static_cast<int>(sigma.unit.rows())),
      share_(distribution.size_, announce(distribution, sigma), sigma.weights) {}

void MpiUkfCovariance::assign(const Eigen::MatrixXd& P) {
  if (P.rows() != n_ || P.cols() != n_)
    throw std::invalid_argument("MpiUkfCovariance::assign: not n x n");
  distribution_.tellWorkers(proto::kCovAssign, n_, n_);
  share_.covariance().scatter(P.data());
}

Eigen::MatrixXd MpiUkfCovariance::matrix() {
  distribution_.tellWorkers(proto::kCovGather, n_, n_);
  Eigen::MatrixXd P(n_, n_);
  share_.covariance().gather(P.data());
  return P;
}

Eigen::VectorXd MpiUkfCovariance::diagonal() {
  distribution_.tellWorkers(proto::kCovDiagonal, n_, 1);
  return share_.covariance().diagonal();
}

void MpiUkfCovariance::addToDiagonal(const Eigen::VectorXd& q) {
  if (q.size() != n_) throw std::invalid_argument("MpiUkfCovariance::addToDiagonal: not n");
  distribution_.tellWorkers(proto::kCovAddDiagonal, n_, 1, q);
  share_.covariance().addToDiagonal(q);
}

void MpiUkfCovariance::forecast(ForecastEnsemble& ensemble, const SigmaPointSet& sigma,
                                const Eigen::VectorXd& x, double spread,
                                Eigen::MatrixXd& observables, RepairLog& repairs) {
  const int s = static_cast<int>(sigma.count());
  Eigen::VectorXd payload(x.size() + 1);
  payload << x, spread;
  distribution_.expectAnswers(s);
  distribution_.tellWorkers(proto::kUkfForecast, n_, s, payload);
  const Eigen::MatrixXd X = share_.drawPoints(x, spread, repairs);
  Eigen::MatrixXd forecasts, own;
  // The workers' answers are taken in even when a forecast here failed, so that every rank is
  // ready for what comes next (a retry of the step, or the end).
  std::exception_ptr failed;
  try {
    ensemble.forecastHere(X, forecasts, own);
    share_.keepForecasts(std::move(forecasts));
  } catch (...) {
    failed = std::current_exception();
  }
  observables.resize(ensemble.observableSize(), s);
  if (!failed) observables.leftCols(own.cols()) = own;
  Eigen::MatrixXd none(0, s);  // the workers keep their forecasts
  distribution_.receive(none, observables);
  if (failed) std::rethrow_exception(failed);
  // Steps after the first (the first faults in its buffers): what a step costs for the model.
  if (++draws_ == 1) return;
  MpiTransferStats& t = distribution_.stats_;
  const UkfShareTimes& times = share_.times();
  ++t.covarianceSteps;
  t.factorSeconds += times.factor;
  t.pdpotrfSeconds += times.pdpotrf;
  t.columnsSeconds += times.columns;
  t.pointsSeconds += times.points;
}

void MpiUkfCovariance::moments(const SigmaPointSet& /*sigma*/, double spread, Eigen::VectorXd& x) {
  distribution_.tellWorkers(proto::kUkfMoments, 1, 1, Eigen::VectorXd::Constant(1, spread));
  x = share_.moments(spread);
  if (draws_ <= 1) return;
  MpiTransferStats& t = distribution_.stats_;
  t.gramSeconds += share_.times().moments;
  t.gramProductSeconds += share_.times().gramProducts;
  t.gramReduceSeconds += share_.times().gramReduce;
}

Eigen::MatrixXd MpiUkfCovariance::correct(const Eigen::MatrixXd& weightedDz,
                                          const Eigen::MatrixXd& C) {
  const Eigen::MatrixXd H = C.triangularView<Eigen::Lower>().solve(weightedDz.transpose());
  distribution_.tellWorkers(proto::kUkfCorrect, static_cast<int>(H.rows()),
                            static_cast<int>(H.cols()));
  Eigen::MatrixXd G = share_.correct(&H, static_cast<int>(H.rows()));
  if (draws_ > 1) distribution_.stats_.correctSeconds += share_.times().correct;
  return G;
}

void MpiUkfCovariance::keep() {
  distribution_.tellWorkers(proto::kCovKeep, n_, n_);
  share_.covariance().keep();
}

void MpiUkfCovariance::restore() {
  distribution_.tellWorkers(proto::kCovRestore, n_, n_);
  share_.covariance().restore();
}

}  // namespace bcassim
