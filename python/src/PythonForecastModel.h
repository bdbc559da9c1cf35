// A ForecastModel and an ObservationOperator written in Python: the trampolines that let a Python
// class (a user's own simulator) be forecast by bcassim's filters. Each call takes the GIL, so the
// filters may run with it released and several worker threads simply take turns in Python.
#pragma once
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include "bcassim/assimilation/ForecastModel.h"
#include "bcassim/assimilation/ObservationOperator.h"

namespace bcassim::python {

// Python side: state_size(), observable_size(), forecast(state, params) -> (new_state,
// observable), and optionally end_step(state, params). Sizes are asked once per call of the
// filter's constructor and checked on every forecast.
class PythonForecastModel : public ForecastModel {
 public:
  Eigen::Index stateSize() const override {
    PYBIND11_OVERRIDE_PURE_NAME(Eigen::Index, ForecastModel, "state_size", stateSize);
  }
  Eigen::Index observableSize() const override {
    PYBIND11_OVERRIDE_PURE_NAME(Eigen::Index, ForecastModel, "observable_size", observableSize);
  }
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& observable) override;
  void endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) override;
  // Optional recentre(state, params) -> bool (RoukfFilter's reforecasts); absent: False.
  bool recentre(const Eigen::VectorXd& state, const Eigen::VectorXd& params) override;
};

// Python side: linearize(mean_observable, frame) -> Observation and predict(observable) ->
// predicted values.
class PythonObservationOperator : public ObservationOperator {
 public:
  Observation linearize(const Eigen::VectorXd& meanObservable, const Observation& frame) override {
    PYBIND11_OVERRIDE_PURE(Observation, ObservationOperator, linearize, meanObservable, frame);
  }
  void predict(const Eigen::VectorXd& observable, Eigen::VectorXd& predicted) const override;
};

}  // namespace bcassim::python
