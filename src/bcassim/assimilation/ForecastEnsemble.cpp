#include "bcassim/assimilation/ForecastEnsemble.h"

#include <fmt/format.h>

#include <stdexcept>

#include "bcassim/Error.h"

namespace bcassim {

ForecastEnsemble::ForecastEnsemble(StochasticState layout, std::vector<ForecastModel*> models,
                                   Executor& executor, bool firstAlone)
    : layout_(std::move(layout)),
      models_(std::move(models)),
      executor_(executor),
      firstAlone_(firstAlone) {
  if (static_cast<int>(models_.size()) < executor_.workers())
    throw InputError(fmt::format("{} forecast models for {} executor workers: one per worker",
                                 models_.size(), executor_.workers()));
  for (const ForecastModel* model : models_) {
    if (model == nullptr) throw InputError("forecast model is null");
    if (model->stateSize() != layout_.physicalSize())
      throw InputError(fmt::format("forecast model state has {} entries, stochastic state {}",
                                   model->stateSize(), layout_.physicalSize()));
    if (model->observationSize() != models_.front()->observationSize())
      throw InputError("forecast models disagree on the number of observations");
  }
  observationSize_ = models_.empty() ? 0 : models_.front()->observationSize();
}

void ForecastEnsemble::forecastColumn(int t, int worker, const Eigen::MatrixXd& points,
                                      Eigen::MatrixXd& forecasts, Eigen::MatrixXd& predicted) {
  const Eigen::Index m = layout_.physicalSize();
  const Eigen::VectorXd state = points.col(t).head(m);
  Eigen::VectorXd params, newState, z;
  layout_.physicalParameters(points.col(t), params);
  models_[worker]->forecast(state, params, newState, z);
  if (newState.size() != m || z.size() != observationSize_)
    throw std::logic_error(fmt::format(
        "forecast model returned {} state and {} observation entries, expected {} and {}",
        newState.size(), z.size(), m, observationSize_));
  if (!newState.allFinite() || !z.allFinite())
    throw NumericalError(fmt::format("forecast of sigma point {} is not finite", t));
  forecasts.col(t).head(m) = newState;
  forecasts.col(t).tail(layout_.parameterCount()) = points.col(t).tail(layout_.parameterCount());
  predicted.col(t) = z;
}

void ForecastEnsemble::forecast(const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                                Eigen::MatrixXd& predicted) {
  const int s = static_cast<int>(points.cols());
  forecasts.resize(points.rows(), s);
  predicted.resize(observationSize_, s);
  auto task = [&](int t, int worker) { forecastColumn(t, worker, points, forecasts, predicted); };
  if (firstAlone_ && s > 1) {
    // Alone and on worker 0, so that the others can reuse what it factorised (Alg. 4/5).
    task(0, 0);
    executor_.run(s - 1, [&](int t, int worker) { task(t + 1, worker); });
  } else {
    executor_.run(s, task);
  }
}

void ForecastEnsemble::endStep(const Eigen::VectorXd& mean) {
  const Eigen::VectorXd state = mean.head(layout_.physicalSize());
  Eigen::VectorXd params;
  layout_.physicalParameters(mean, params);
  for (ForecastModel* model : models_) model->endStep(state, params);
}

}  // namespace bcassim
