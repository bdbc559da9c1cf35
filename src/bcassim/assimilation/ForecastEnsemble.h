// The forecast step shared by every filter: advance a set of stochastic states (sigma points or
// ensemble members) through the ForecastModels, in parallel, and collect predicted observations.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/assimilation/Executor.h"
#include "bcassim/assimilation/ForecastModel.h"
#include "bcassim/assimilation/StochasticState.h"

namespace bcassim {

class ForecastEnsemble {
 public:
  // models[w] is used by executor worker w; models.size() >= executor.workers(). The models and
  // the executor must outlive this object. Throws InputError if sizes disagree with `layout`.
  ForecastEnsemble(StochasticState layout, std::vector<ForecastModel*> models, Executor& executor,
                   bool firstAlone);

  const StochasticState& layout() const { return layout_; }
  Eigen::Index observationSize() const { return observationSize_; }

  // Column t of `points` (layout().size() x s) is forecast one step: physical rows advanced by the
  // model, parameter rows carried over (parameters are constant in time, eq. 3.1 with T = Id on
  // them). Writes forecasts (same shape) and predicted observations (observationSize() x s).
  // Throws NumericalError if a model returns non-finite values.
  void forecast(const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                Eigen::MatrixXd& predicted);

  // Tells every model, in worker order, that the step ended at the analysed mean (unconstrained).
  void endStep(const Eigen::VectorXd& mean);

 private:
  void forecastColumn(int t, int worker, const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                      Eigen::MatrixXd& predicted);

  StochasticState layout_;
  std::vector<ForecastModel*> models_;
  Executor& executor_;
  bool firstAlone_;
  Eigen::Index observationSize_ = 0;
};

}  // namespace bcassim
