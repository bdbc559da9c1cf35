// The forecast step shared by every filter: advance a set of stochastic states (sigma points or
// ensemble members) through the ForecastModels, in parallel, then predict their observations
// through the step's ObservationOperator, linearised at the forecasts' mean.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "bcassim/assimilation/Executor.h"
#include "bcassim/assimilation/ForecastDistribution.h"
#include "bcassim/assimilation/ForecastModel.h"
#include "bcassim/assimilation/ObservationOperator.h"
#include "bcassim/assimilation/StochasticState.h"

namespace bcassim {

// What ForecastEnsemble::forecastRetrying had to do: the halvings of the points' spread (0: the
// first try served) and the first failure's message.
struct ForecastRetries {
  int halvings = 0;
  std::string failure;
  double spread = 1.0;  // the points' distance from the mean that served, relative to their own
};

// The retry policy of a step's forecasts, for every filter: attempt(spread) with spread 1, 1/2,
// 1/4, ... until one returns without a NumericalError, at most retries + 1 calls; the last
// failure is rethrown as it was.
ForecastRetries retryCloserToTheMean(int retries,
                                     const std::function<void(double spread)>& attempt);

class ForecastEnsemble {
 public:
  // models[w] is used by executor worker w; models.size() >= executor.workers(). The models and
  // the executor must outlive this object; so must `observation` (null: DirectObservation) and
  // `distribution` (null: every column is forecast here). Throws InputError if sizes disagree
  // with `layout`.
  ForecastEnsemble(StochasticState layout, std::vector<ForecastModel*> models, Executor& executor,
                   bool firstAlone, ObservationOperator* observation = nullptr,
                   ForecastDistribution* distribution = nullptr);

  const StochasticState& layout() const { return layout_; }
  Eigen::Index observableSize() const { return observableSize_; }

  // Column t of `points` (layout().size() x s) is forecast one step: physical rows advanced by the
  // model, parameter rows carried over (parameters are constant in time, eq. 3.1 with T = Id on
  // them; a random walk enters as the filters' process noise). Writes forecasts (same shape) and
  // the forecasts' observables (observableSize() x s). Throws NumericalError if a model returns
  // non-finite values. With a distribution, the columns past its localColumns() are forecast by
  // the other processes, the same way.
  void forecast(const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                Eigen::MatrixXd& observables);
  // forecast() that survives a failed forecast: when one throws NumericalError (a model step
  // that failed even at its smallest time step: an element inverted by a sigma point far out in
  // the parameters), every point is moved halfway to the points' mean (`weights`, summing to 1)
  // and all are forecast again, up to `retries` times. The forecasts' and the observables'
  // deviations from their means are then stretched back by the same factor: exact for a linear
  // model (a scaled unscented transform of spread 2^-k), so the filter's covariance keeps its
  // meaning and only the curvature the far points would have seen is lost. Returns the
  // halvings the step needed and the first failure's message. When the retries are spent,
  // rethrows the last failure as the model threw it.
  ForecastRetries forecastRetrying(const Eigen::MatrixXd& points, const Eigen::VectorXd& weights,
                                   int retries, Eigen::MatrixXd& forecasts,
                                   Eigen::MatrixXd& observables);
  // The same for every column here, whatever the distribution: a process forecasting the sigma
  // points it formed itself (a distributed UKF covariance, UkfCovariance.h).
  void forecastHere(const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                    Eigen::MatrixXd& observables);

  // After forecast(), for a frame with data: linearises the observation operator at the mean of
  // the observables (column weights `weights`, summing to 1) and predicts every column's
  // observation into `predicted` (entries x s). Returns the frame as the filter must use it
  // (ObservationOperator::linearize). A frame without data is returned as it is, `predicted`
  // emptied. Throws NumericalError if a prediction is not finite. With `analysed` (one coefficient
  // per column), the operator is linearised instead at the mean moved by the anomalies' linear
  // combination sum_t analysed_t (o_t - mean): where a correction that writes the state's update
  // as that combination puts the observables (a relinearisation, FilterOptions).
  Observation predict(const Observation& frame, const Eigen::VectorXd& weights,
                      const Eigen::MatrixXd& observables, Eigen::MatrixXd& predicted,
                      const Eigen::VectorXd& analysed = Eigen::VectorXd());

  // Tells every model, in worker order, that the step ended at the analysed mean (unconstrained);
  // the distribution's first, so that the other processes move on while these do.
  // A model's NumericalError comes out as a NumericalError "the analysed mean: ...".
  void endStep(const Eigen::VectorXd& mean);
  // Asks every model, in worker order, to re-centre the step on the analysed mean
  // (ForecastModel::recentre): whether forecasts about it can change the analysis. False, asking
  // none, where forecasts are shared with other processes (not supported there); a
  // NumericalError comes out as endStep()'s does.
  bool recentre(const Eigen::VectorXd& mean);

 private:
  void forecastColumns(int s, const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                       Eigen::MatrixXd& observables);
  void forecastColumn(int t, int worker, const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                      Eigen::MatrixXd& observables);

  StochasticState layout_;
  std::vector<ForecastModel*> models_;
  Executor& executor_;
  bool firstAlone_;
  DirectObservation direct_;
  ObservationOperator* observation_;    // null: direct_
  ForecastDistribution* distribution_;  // null: every column here
  Eigen::Index observableSize_ = 0;
};

}  // namespace bcassim
