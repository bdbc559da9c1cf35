#include "bcassim/assimilation/ForecastEnsemble.h"

#include <fmt/format.h>

#include <exception>
#include <functional>
#include <stdexcept>

#include "bcassim/Error.h"

namespace bcassim {

ForecastEnsemble::ForecastEnsemble(StochasticState layout, std::vector<ForecastModel*> models,
                                   Executor& executor, bool firstAlone,
                                   ObservationOperator* observation,
                                   ForecastDistribution* distribution)
    : layout_(std::move(layout)),
      models_(std::move(models)),
      executor_(executor),
      firstAlone_(firstAlone),
      observation_(observation),
      distribution_(distribution) {
  if (static_cast<int>(models_.size()) < executor_.workers())
    throw InputError(fmt::format("{} forecast models for {} executor workers: one per worker",
                                 models_.size(), executor_.workers()));
  for (const ForecastModel* model : models_) {
    if (model == nullptr) throw InputError("forecast model is null");
    if (model->stateSize() != layout_.physicalSize())
      throw InputError(fmt::format("forecast model state has {} entries, stochastic state {}",
                                   model->stateSize(), layout_.physicalSize()));
    if (model->observableSize() != models_.front()->observableSize())
      throw InputError("forecast models disagree on the size of their observables");
  }
  observableSize_ = models_.empty() ? 0 : models_.front()->observableSize();
}

void ForecastEnsemble::forecastColumn(int t, int worker, const Eigen::MatrixXd& points,
                                      Eigen::MatrixXd& forecasts, Eigen::MatrixXd& observables) {
  const Eigen::Index m = layout_.physicalSize();
  const Eigen::VectorXd state = points.col(t).head(m);
  Eigen::VectorXd params, newState, o;
  layout_.physicalParameters(points.col(t), params);
  models_[worker]->forecast(state, params, newState, o);
  if (newState.size() != m || o.size() != observableSize_)
    throw std::logic_error(fmt::format(
        "forecast model returned {} state and {} observable entries, expected {} and {}",
        newState.size(), o.size(), m, observableSize_));
  if (!newState.allFinite() || !o.allFinite())
    throw NumericalError(fmt::format("forecast of sigma point {} is not finite", t));
  forecasts.col(t).head(m) = newState;
  forecasts.col(t).tail(layout_.parameterCount()) = points.col(t).tail(layout_.parameterCount());
  observables.col(t) = o;
}

void ForecastEnsemble::forecast(const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                                Eigen::MatrixXd& observables) {
  const int columns = static_cast<int>(points.cols());
  forecasts.resize(points.rows(), columns);
  observables.resize(observableSize_, columns);
  // The other processes' columns leave first, so that they run while these do.
  const int s = distribution_ ? distribution_->localColumns(columns) : columns;
  if (s == columns) {
    forecastColumns(s, points, forecasts, observables);
    return;
  }
  distribution_->send(points);
  // The other processes' answers are taken in even when a forecast here failed, so that the
  // processes stay in step for whatever comes next (a retry of the step, or the end).
  std::exception_ptr failed;
  try {
    forecastColumns(s, points, forecasts, observables);
  } catch (...) {
    failed = std::current_exception();
  }
  distribution_->receive(forecasts, observables);
  if (failed) std::rethrow_exception(failed);
}

ForecastRetries retryCloserToTheMean(int retries,
                                     const std::function<void(double spread)>& attempt) {
  ForecastRetries done;
  for (;;) {
    try {
      attempt(done.spread);
      return done;
    } catch (const NumericalError& e) {
      if (done.halvings == 0) done.failure = e.what();
      if (done.halvings == retries) throw;  // the model's own error, as the caller knows it
      ++done.halvings;
      done.spread /= 2;
    }
  }
}

ForecastRetries ForecastEnsemble::forecastRetrying(const Eigen::MatrixXd& points,
                                                   const Eigen::VectorXd& weights, int retries,
                                                   Eigen::MatrixXd& forecasts,
                                                   Eigen::MatrixXd& observables) {
  ForecastRetries done = retryCloserToTheMean(retries, [&](double k) {
    if (k == 1.0) {
      forecast(points, forecasts, observables);
      return;
    }
    const Eigen::VectorXd centre = points * weights;  // only once a forecast has failed
    forecast((k * (points.colwise() - centre)).colwise() + centre, forecasts, observables);
  });
  if (done.halvings == 0) return done;
  const auto stretch = [&](Eigen::MatrixXd& m) {
    const Eigen::VectorXd mean = m * weights;
    m = ((m.colwise() - mean) / done.spread).colwise() + mean;
  };
  stretch(forecasts);
  stretch(observables);
  return done;
}

void ForecastEnsemble::forecastHere(const Eigen::MatrixXd& points, Eigen::MatrixXd& forecasts,
                                    Eigen::MatrixXd& observables) {
  forecasts.resize(points.rows(), points.cols());
  observables.resize(observableSize_, points.cols());
  forecastColumns(static_cast<int>(points.cols()), points, forecasts, observables);
}

// Columns [0, s) of `points`, on the executor's workers.
void ForecastEnsemble::forecastColumns(int s, const Eigen::MatrixXd& points,
                                       Eigen::MatrixXd& forecasts, Eigen::MatrixXd& observables) {
  auto task = [&](int t, int worker) { forecastColumn(t, worker, points, forecasts, observables); };
  if (firstAlone_ && s > 1) {
    // Alone and on worker 0, so that the others can reuse what it factorised (Alg. 4/5).
    task(0, 0);
    executor_.run(s - 1, [&](int t, int worker) { task(t + 1, worker); });
  } else {
    executor_.run(s, task);
  }
}

Observation ForecastEnsemble::predict(const Observation& frame, const Eigen::VectorXd& weights,
                                      const Eigen::MatrixXd& observables,
                                      Eigen::MatrixXd& predicted, const Eigen::VectorXd& analysed) {
  if (frame.values.size() == 0) {
    predicted.resize(0, observables.cols());
    return frame;
  }
  ObservationOperator& op = observation_ ? *observation_ : direct_;
  Eigen::VectorXd mean = observables * weights;
  if (analysed.size() != 0) {
    if (analysed.size() != observables.cols())
      throw std::logic_error("ForecastEnsemble::predict: one analysed coefficient per column");
    mean += (observables.colwise() - mean) * analysed;
  }
  Observation used = op.linearize(mean, frame);
  const Eigen::Index m = used.values.size();
  const int s = static_cast<int>(observables.cols());
  predicted.resize(m, s);
  executor_.run(s, [&](int t, int) {
    Eigen::VectorXd z;
    op.predict(observables.col(t), z);
    if (z.size() != m)
      throw std::logic_error(
          fmt::format("observation operator predicted {} entries for a frame of {}", z.size(), m));
    if (!z.allFinite())
      throw NumericalError(fmt::format("predicted observation of sigma point {} is not finite", t));
    predicted.col(t) = z;
  });
  return used;
}

void ForecastEnsemble::endStep(const Eigen::VectorXd& mean) {
  const Eigen::VectorXd state = mean.head(layout_.physicalSize());
  Eigen::VectorXd params;
  layout_.physicalParameters(mean, params);
  if (distribution_) distribution_->endStep(mean);
  // Not a forecast's failure (a static model solving the mean's own equilibrium, say): named so,
  // and no longer of the model's type, which callers read as a forecast's.
  try {
    for (ForecastModel* model : models_) model->endStep(state, params);
  } catch (const NumericalError& e) {
    throw NumericalError(fmt::format("the analysed mean: {}", e.what()));
  }
}

bool ForecastEnsemble::recentre(const Eigen::VectorXd& mean) {
  if (distribution_ || models_.empty()) return false;
  const Eigen::VectorXd state = mean.head(layout_.physicalSize());
  Eigen::VectorXd params;
  layout_.physicalParameters(mean, params);
  try {
    // Every model, whatever the first answers: each may have moved its reference.
    const bool worthwhile = models_.front()->recentre(state, params);
    for (size_t i = 1; i < models_.size(); ++i)
      if (models_[i]->recentre(state, params) != worthwhile)
        throw std::logic_error("ForecastEnsemble::recentre: the models answered differently");
    return worthwhile;
  } catch (const NumericalError& e) {
    throw NumericalError(fmt::format("the analysed mean: {}", e.what()));
  }
}

}  // namespace bcassim
