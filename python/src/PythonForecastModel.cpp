#include "PythonForecastModel.h"

#include <string>

namespace py = pybind11;

namespace bcassim::python {

namespace {
Eigen::VectorXd vectorOf(const py::handle& value, Eigen::Index expected, const char* what) {
  auto v = py::cast<Eigen::VectorXd>(
      py::array_t<double, py::array::forcecast>::ensure(value).attr("ravel")());
  if (v.size() != expected)
    throw py::value_error(std::string("ForecastModel.forecast: ") + what + " has " +
                          std::to_string(v.size()) + " entries, expected " +
                          std::to_string(expected));
  return v;
}
}  // namespace

void PythonForecastModel::forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                                   Eigen::VectorXd& newState, Eigen::VectorXd& observable) {
  py::gil_scoped_acquire gil;
  const py::function override =
      py::get_override(static_cast<const ForecastModel*>(this), "forecast");
  if (!override) py::pybind11_fail("ForecastModel.forecast is not implemented");
  const py::object result = override(state, params);
  if (!py::isinstance<py::tuple>(result) || py::len(result) != 2)
    throw py::type_error("ForecastModel.forecast must return (new_state, observable)");
  const auto pair = py::reinterpret_borrow<py::tuple>(result);
  newState = vectorOf(pair[0], stateSize(), "new_state");
  observable = vectorOf(pair[1], observableSize(), "observable");
}

void PythonForecastModel::endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) {
  py::gil_scoped_acquire gil;
  const py::function override =
      py::get_override(static_cast<const ForecastModel*>(this), "end_step");
  if (override) override(state, params);  // optional: a model without reference state needs none
}

bool PythonForecastModel::recentre(const Eigen::VectorXd& state, const Eigen::VectorXd& params) {
  py::gil_scoped_acquire gil;
  const py::function override =
      py::get_override(static_cast<const ForecastModel*>(this), "recentre");
  return override && py::cast<bool>(override(state, params));  // optional: a model cannot
}

void PythonObservationOperator::predict(const Eigen::VectorXd& observable,
                                        Eigen::VectorXd& predicted) const {
  py::gil_scoped_acquire gil;
  const py::function override =
      py::get_override(static_cast<const ObservationOperator*>(this), "predict");
  if (!override) py::pybind11_fail("ObservationOperator.predict is not implemented");
  predicted = py::cast<Eigen::VectorXd>(
      py::array_t<double, py::array::forcecast>::ensure(override(observable)).attr("ravel")());
}

}  // namespace bcassim::python
