// Forecasts of one step shared with other processes (e.g. MPI ranks, distributed/): the
// ForecastEnsemble keeps the first columns, the distribution the others. No MPI here.
#pragma once
#include <Eigen/Core>

#include "bcassim/assimilation/DenseAlgebra.h"

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
  // The filter's dense algebra shared with the other processes (they hold the last forecasts'
  // columns they computed), or null: the filter runs it alone. Calls come between receive() and
  // endStep() for the Gram matrix, anywhere between steps for Cholesky factors.
  virtual DenseAlgebra* sharedAlgebra() { return nullptr; }
};

}  // namespace bcassim
