// bcassim.assimilation: the stochastic state, observations and the three filters (UKF, ROUKF,
// ETKF) over any ForecastModel, including one written in Python (a subclass of
// bcassim.assimilation.ForecastModel). A step runs with the GIL released; Python models take it
// back for their own calls, so `threads` > 1 overlaps C++ work only.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "Bindings.h"
#include "PythonForecastModel.h"
#include "bcassim/assimilation/EtkfFilter.h"
#include "bcassim/assimilation/RoukfFilter.h"
#include "bcassim/assimilation/ThreadPoolExecutor.h"
#include "bcassim/assimilation/UkfFilter.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

namespace {

// A filter with what it points to: the Python models (kept alive here), the executor and the
// observation operator. The filters hold raw pointers; this object outlives them.
struct FilterHandle {
  std::vector<py::object> modelObjects;
  py::object observationObject;
  std::unique_ptr<Executor> executor;
  std::unique_ptr<StochasticState> layout;
  std::unique_ptr<Filter> filter;
  FilterStepReport last;
};

struct RoukfHandle : FilterHandle {};
struct UkfHandle : FilterHandle {};
struct EtkfHandle : FilterHandle {};

// Models for `threads` workers: one model serves one worker, so a list needs >= threads entries.
std::vector<ForecastModel*> modelsFor(FilterHandle& h, const py::object& models, int threads) {
  if (threads < 1) throw py::value_error("threads: expected >= 1, got " + std::to_string(threads));
  std::vector<py::object> list;
  if (py::isinstance<ForecastModel>(models))
    list.push_back(models);
  else
    for (auto item : models) list.push_back(py::reinterpret_borrow<py::object>(item));
  if (static_cast<int>(list.size()) < threads)
    throw py::value_error("models: " + std::to_string(list.size()) + " for " +
                          std::to_string(threads) +
                          " threads; give one ForecastModel per thread (they run concurrently)");
  std::vector<ForecastModel*> raw;
  for (const py::object& o : list) raw.push_back(py::cast<ForecastModel*>(o));
  h.modelObjects = std::move(list);
  h.executor = threads == 1 ? std::unique_ptr<Executor>(std::make_unique<SerialExecutor>())
                            : std::make_unique<ThreadPoolExecutor>(threads);
  return raw;
}

ObservationOperator* observationFor(FilterHandle& h, const py::object& observation) {
  if (observation.is_none()) return nullptr;
  h.observationObject = observation;
  return py::cast<ObservationOperator*>(observation);
}

Eigen::VectorXd processVarianceOf(const std::optional<Eigen::VectorXd>& q) {
  return q ? *q : Eigen::VectorXd();
}

Observation observationFromValues(Eigen::VectorXd values, std::optional<double> sigma,
                                  std::optional<Eigen::VectorXd> variance,
                                  std::optional<Eigen::MatrixXd> covariance,
                                  std::optional<std::vector<bool>> present) {
  Observation y;
  y.values = std::move(values);
  if (sigma) y.variance = Eigen::VectorXd::Constant(y.values.size(), *sigma * *sigma);
  if (variance) y.variance = *variance;
  if (covariance) y.covariance = *covariance;
  if (present) y.present = *present;
  if (y.values.size() && y.variance.size() == 0 && y.covariance.size() == 0)
    throw py::value_error("Observation: give sigma, variance or covariance (noise of the values)");
  return y;
}

// The filter of handle type H (FilterT over OptionsT), once the kind's own options are set: the
// options every filter shares, its models and executor.
template <class H, class FilterT, class OptionsT>
std::unique_ptr<H> makeFilter(const StochasticState& layout, const py::object& models, int threads,
                              OptionsT o, const std::optional<Eigen::VectorXd>& q, bool firstAlone,
                              const py::object& observation, int relinearizations) {
  auto h = std::make_unique<H>();
  o.processVariance = processVarianceOf(q);
  o.relinearizations = relinearizations;
  o.firstSigmaPointAlone = firstAlone;
  o.observation = observationFor(*h, observation);
  auto raw = modelsFor(*h, models, threads);
  h->layout = std::make_unique<StochasticState>(layout);
  h->filter = std::make_unique<FilterT>(layout, raw, *h->executor, o);
  return h;
}

}  // namespace

void bindAssimilation(py::module_& m) {
  py::class_<ParameterTransform>(m, "ParameterTransform",
                                 "Physical value <-> the unconstrained value a filter estimates")
      .def(py::init([](const std::string& kind, double lower, double upper) {
             switch (parseTransformKind(kind)) {
               case TransformKind::Identity:
                 return ParameterTransform::identity();
               case TransformKind::Absolute:
                 return ParameterTransform::absolute();
               case TransformKind::Exponential:
                 return ParameterTransform::exponential();
               case TransformKind::Projection:
                 return ParameterTransform::projection(lower, upper);
               case TransformKind::BoundedLog:
                 return ParameterTransform::boundedLog(lower, upper);
             }
             return ParameterTransform();
           }),
           "kind"_a = "none", "lower"_a = 0.0, "upper"_a = 0.0,
           "kind: none, abs, exp (log), projection or bounded-log (the last two with lower < "
           "upper, in the parameter's SI unit)")
      .def("to_physical", &ParameterTransform::toPhysical, "u"_a)
      .def("to_unconstrained", &ParameterTransform::toUnconstrained, "value"_a);

  py::class_<Parameter>(m, "Parameter", "One estimated scalar: initial mean and sigma (SI units)")
      .def(py::init([](std::string name, double mean, double stddev, ParameterTransform t) {
             return Parameter{std::move(name), mean, stddev, t};
           }),
           "name"_a, "mean"_a, "stddev"_a, "transform"_a = ParameterTransform())
      .def_readwrite("name", &Parameter::name)
      .def_readwrite("mean", &Parameter::mean)
      .def_readwrite("stddev", &Parameter::stddev);

  py::class_<StochasticState>(
      m, "StochasticState",
      "Layout x = [physical part; parameters]: the physical part's initial mean and sigma (may "
      "be empty, or 0 where known exactly), then the parameters")
      .def(py::init<Eigen::VectorXd, Eigen::VectorXd, std::vector<Parameter>>(), "physical_mean"_a,
           "physical_stddev"_a, "parameters"_a)
      .def_property_readonly("size", &StochasticState::size)
      .def_property_readonly("physical_size", &StochasticState::physicalSize)
      .def_property_readonly("parameters", &StochasticState::parameters)
      .def("initial_mean", &StochasticState::initialMean, "Unconstrained initial mean")
      .def("initial_stddev", &StochasticState::initialStddev, "Unconstrained initial sigma");

  py::class_<Observation>(m, "Observation",
                          "One frame of measurements with its noise (SI units); entries may be "
                          "absent (present[i] False)")
      .def(py::init(&observationFromValues), "values"_a, "sigma"_a = py::none(),
           "variance"_a = py::none(), "covariance"_a = py::none(), "present"_a = py::none())
      .def_readwrite("values", &Observation::values)
      .def_readwrite("variance", &Observation::variance)
      .def_readwrite("covariance", &Observation::covariance)
      .def_readwrite("present", &Observation::present);

  py::class_<StepSeconds>(m, "StepSeconds")
      .def_readonly("forecast", &StepSeconds::forecast)
      .def_readonly("correction", &StepSeconds::correction)
      .def_readonly("total", &StepSeconds::total);
  py::class_<FilterStepReport>(m, "StepReport",
                               "A step's analysed mean and sigma (physical units: the physical "
                               "part, then the parameters transformed back)")
      .def_readonly("mean", &FilterStepReport::mean)
      .def_readonly("stddev", &FilterStepReport::stddev)
      .def_readonly("innovation_norm", &FilterStepReport::innovationNorm)
      .def_readonly("innovation_squared_norm", &FilterStepReport::innovationSquaredNorm)
      .def_readonly("predicted_observation_trace", &FilterStepReport::predictedObservationTrace)
      .def_readonly("observed", &FilterStepReport::observed)
      .def_readonly("relinearizations", &FilterStepReport::relinearizations)
      .def_readonly("reforecasts", &FilterStepReport::reforecasts)
      .def_readonly("covariance_repairs", &FilterStepReport::covarianceRepairs)
      .def_readonly("seconds", &FilterStepReport::seconds);

  py::class_<ForecastModel, PythonForecastModel>(
      m, "ForecastModel",
      "Subclass it: state_size(), observable_size(), forecast(state, params) -> (new_state, "
      "observable) advancing one time step (params in physical units), and optionally "
      "end_step(state, params) with the analysed mean, and recentre(state, params) -> bool for "
      "RoukfFilter's reforecasts (a static model: its reference moved to the equilibrium at "
      "these values within the step; True where forecasts about it can change the analysis). "
      "forecast must depend only on its arguments and the model's reference (set by end_step "
      "and recentre).")
      .def(py::init<>());

  py::class_<ObservationOperator, PythonObservationOperator>(
      m, "ObservationOperator",
      "Subclass it: linearize(mean_observable, frame) -> Observation fixes the operator for the "
      "step; predict(observable) -> predicted values")
      .def(py::init<>());

  py::class_<FilterHandle>(m, "Filter", "A Kalman filter over ForecastModels")
      .def(
          "step",
          [](FilterHandle& h, const std::optional<Observation>& y) {
            {
              py::gil_scoped_release release;
              h.last = h.filter->step(y ? *y : Observation::none());
            }
            return h.last;
          },
          "observation"_a = py::none(),
          "Forecasts every sigma point / member one step and corrects with the observation "
          "(None: prediction only)")
      .def_property_readonly(
          "mean", [](const FilterHandle& h) { return Eigen::VectorXd(h.filter->mean()); },
          "Mean of x in the filter's unconstrained space")
      .def("covariance", [](const FilterHandle& h) { return h.filter->covariance(); })
      .def("covariance_factor", [](const FilterHandle& h) { return h.filter->covarianceFactor(); })
      .def(
          "estimate",
          [](const FilterHandle& h) {
            const Eigen::VectorXd sd = h.filter->covariance().diagonal().cwiseSqrt();
            Eigen::VectorXd mean, stddev;
            h.layout->toReported(h.filter->mean(), sd, mean, stddev);
            return py::make_tuple(mean, stddev);
          },
          "(mean, stddev) in physical units: the physical part, then the parameters");

  py::class_<RoukfHandle, FilterHandle>(m, "RoukfFilter",
                                        "Reduced-order UKF (thesis Alg. 2): rank = parameters")
      .def(py::init([](const StochasticState& layout, const py::object& models, int threads,
                       const std::string& sigmaPoints, std::optional<Eigen::VectorXd> q,
                       bool firstAlone, const py::object& observation, int relinearizations,
                       int reforecasts, double reforecastBeyond) {
             RoukfOptions o;
             o.sigmaPoints = parseSigmaPointKind(sigmaPoints);
             o.reforecasts = reforecasts;
             o.reforecastBeyond = reforecastBeyond;
             return makeFilter<RoukfHandle, RoukfFilter>(layout, models, threads, o, q, firstAlone,
                                                         observation, relinearizations);
           }),
           "layout"_a, "models"_a, "threads"_a = 1, "sigma_points"_a = "simplex",
           "process_variance"_a = py::none(), "first_alone"_a = false, "observation"_a = py::none(),
           "relinearizations"_a = 0, "reforecasts"_a = 0, "reforecast_beyond"_a = 1.0,
           "models: a ForecastModel, or a list of one per thread; process_variance: unconstrained "
           "variance per state entry per step (random walk of the parameters); relinearizations: "
           "analysis passes after the first that linearise the observation operator again at the "
           "analysed observables (an iterated filter for the operator, no forecast repeated); "
           "reforecasts (parameters-only states): where the analysis moves the mean by more than "
           "reforecast_beyond forecast standard deviations, the models are re-centred on it "
           "(ForecastModel.recentre) and the step forecast and analysed again, up to this many "
           "times");

  py::class_<UkfHandle, FilterHandle>(m, "UkfFilter", "Unscented Kalman filter (thesis Alg. 1)")
      .def(py::init([](const StochasticState& layout, const py::object& models, int threads,
                       const std::string& sigmaPoints, double spread, double kappa,
                       std::optional<Eigen::VectorXd> q, bool firstAlone,
                       const py::object& observation, int relinearizations) {
             UkfOptions o;
             o.sigmaPoints = parseSigmaPointKind(sigmaPoints);
             o.spread = spread;
             o.starKappa = kappa;
             return makeFilter<UkfHandle, UkfFilter>(layout, models, threads, o, q, firstAlone,
                                                     observation, relinearizations);
           }),
           "layout"_a, "models"_a, "threads"_a = 1, "sigma_points"_a = "star", "spread"_a = 1.0,
           "kappa"_a = 0.0, "process_variance"_a = py::none(), "first_alone"_a = false,
           "observation"_a = py::none(), "relinearizations"_a = 0);

  py::class_<EtkfHandle, FilterHandle>(m, "EtkfFilter",
                                       "Ensemble transform Kalman filter (thesis Alg. 3)")
      .def(py::init([](const StochasticState& layout, const py::object& models, int threads,
                       int members, std::uint64_t seed, std::optional<Eigen::VectorXd> q,
                       bool firstAlone, const py::object& observation, int relinearizations) {
             EtkfOptions o;
             o.members = members;
             o.seed = seed;
             return makeFilter<EtkfHandle, EtkfFilter>(layout, models, threads, o, q, firstAlone,
                                                       observation, relinearizations);
           }),
           "layout"_a, "models"_a, "threads"_a = 1, "members"_a = 10, "seed"_a = 1,
           "process_variance"_a = py::none(), "first_alone"_a = false, "observation"_a = py::none(),
           "relinearizations"_a = 0)
      .def_property_readonly("members", [](const EtkfHandle& h) {
        return static_cast<const EtkfFilter&>(*h.filter).members();
      });
}

}  // namespace bcassim::python
