// Forecasts of one step shared with other processes (e.g. MPI ranks, distributed/): the
// ForecastEnsemble keeps the first columns, the distribution the others. No MPI here.
#pragma once
#include <Eigen/Core>
#include <memory>

#include "bcassim/assimilation/UkfCovariance.h"

namespace bcassim {

// Contract: the other processes hold the same models, layout and reference as this one (built
// from the same scene) and forecast exactly as ForecastEnsemble::forecast does, so that where a
// column is forecast changes nothing. Calls come in this order each step: send, receive (unless
// this process's own forecasts threw in between), then endStep.
class ForecastDistribution {
 public:
  virtual ~ForecastDistribution() = default;

  // Of `columns` sigma points / members, how many this process forecasts itself: the first ones.
  virtual int localColumns(int columns) const = 0;
  // The run's step the next forecasts belong to (1-based), for the messages of a failure.
  virtual void beginStep(int /*step*/) {}
  // Hands columns [localColumns(n), n) of `points` (rows x n) to the other processes and returns
  // without waiting for their forecasts.
  virtual void send(const Eigen::MatrixXd& points) = 0;
  // Waits for the forecasts of the columns sent and writes them, and their observables, into the
  // same columns of `forecasts` and `observables` (already sized). Rethrows another process's
  // error, naming it, once every answer is in.
  virtual void receive(Eigen::MatrixXd& forecasts, Eigen::MatrixXd& observables) = 0;
  // The step ended at the analysed mean (unconstrained): the other processes' models move on.
  virtual void endStep(const Eigen::VectorXd& mean) = 0;
  // A full-state UKF's covariance kept by this process and the others together (each forms and
  // forecasts its own sigma points of `sigma` from its share of the factor), or null: the filter
  // keeps it here and the columns travel through send() and receive().
  virtual std::unique_ptr<UkfCovariance> ukfCovariance(const SigmaPointSet& /*sigma*/) {
    return nullptr;
  }
};

}  // namespace bcassim
