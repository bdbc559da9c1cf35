// bcassim.scene: a YAML scene (docs/scene-format.md) loaded, changed (materials, spring
// coefficients, load forces), run step by step (Simulation) or through the commands' runners
// (simulate, assimilate, validate: the same files as the command line, a callback per step).
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "Positions.h"
#include "SceneSimulation.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/ModelParameter.h"
#include "bcassim/scene/SceneLoader.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

namespace {
// A Python callback called from C++ with the GIL released around the run: take it back per call.
template <typename Progress>
std::function<void(const Progress&)> withGil(const std::optional<py::function>& callback) {
  if (!callback) return {};
  // Copies of the std::function made while the GIL is released copy the shared_ptr only, never a
  // Python reference; the caller creates and destroys it with the GIL held.
  auto f = std::make_shared<py::function>(*callback);
  return [f](const Progress& p) {
    py::gil_scoped_acquire gil;
    (*f)(p);
  };
}

py::dict runResultDict(const RunResult& r) {
  return py::dict("name"_a = r.name, "out_dir"_a = r.outDir, "steps"_a = r.steps,
                  "frames"_a = r.frames, "mean_step_ms"_a = r.meanStepMs,
                  "wall_seconds"_a = r.wallSeconds,
                  "max_marker_displacement_m"_a = r.maxMarkerDisplacement,
                  "max_node_displacement_m"_a = r.maxNodeDisplacement,
                  "relative_difference_final"_a = r.relativeDifferenceFinal,
                  "relative_difference_all"_a = r.relativeDifferenceAll);
}
}  // namespace

void bindScene(py::module_& m) {
  py::class_<MarkerSet>(m, "PointSet", "Points of the scene mapped into the rest mesh")
      .def_readonly("rest", &MarkerSet::rest, "#points x 3 rest positions (m)")
      .def("__len__", [](const MarkerSet& s) { return s.points.size(); });

  py::class_<EstimatedParameter>(m, "EstimatedParameter",
                                 "A parameter of the scene's assimilation: section (SI units)")
      .def_readonly("name", &EstimatedParameter::name)
      .def_readonly("mean", &EstimatedParameter::mean)
      .def_readonly("stddev", &EstimatedParameter::stddev)
      .def_readonly("truth", &EstimatedParameter::truth);

  py::class_<Scene>(m, "Scene", "A scene ready to run (bcassim.scene.load)")
      .def_readonly("name", &Scene::name)
      .def_readonly("source_file", &Scene::sourceFile)
      .def_readwrite("model", &Scene::model, "The mechanical model (bcassim.mechanics.Model)")
      .def_readwrite("steps", &Scene::steps)
      .def_property_readonly("dt", &Scene::dt, "Time step, s")
      .def_readonly("markers", &Scene::markers)
      .def_readonly("validation_points", &Scene::validation)
      .def_readonly("hidden_points", &Scene::hidden)
      .def_property_readonly(
          "parameters",
          [](const Scene& s) {
            return s.assimilation ? s.assimilation->parameters : std::vector<EstimatedParameter>();
          },
          "Parameters the assimilation: section estimates, with their priors")
      .def(
          "set_young_modulus",
          [](Scene& s, int region, double E, const std::string& law, double nu) {
            applyParameter(YoungModulusTarget{region, law, nu}, E, s.model);
          },
          "region"_a, "E"_a, "law"_a = "stvk", "nu"_a = 0.49,
          "Material of a region rebuilt with Young's modulus E (Pa), the law and Poisson's ratio")
      .def(
          "set_spring_coefficients",
          [](Scene& s, int group, std::optional<double> ka, std::optional<double> kb,
             std::optional<double> kg) {
            const double values[3] = {ka.value_or(NAN), kb.value_or(NAN), kg.value_or(NAN)};
            const bool given[3] = {ka.has_value(), kb.has_value(), kg.has_value()};
            for (int c = 0; c < 3; ++c)
              if (given[c]) applyParameter(SpringCoefficientTarget{group, c}, values[c], s.model);
          },
          "group"_a, "k_alpha"_a = py::none(), "k_beta"_a = py::none(), "k_gamma"_a = py::none(),
          "Coefficients of a spring group: k_alpha N/m^3, k_beta N/m^2, k_gamma N/m")
      .def(
          "set_load_force",
          [](Scene& s, int load, const Vec3& force) {
            for (int c = 0; c < 3; ++c) applyParameter(LoadForceTarget{load, c}, force(c), s.model);
          },
          "load"_a, "force"_a, "Total force (N, 3 components) of a load of the scene")
      .def(
          "load_force",
          [](const Scene& s, int load) {
            Vec3 f;
            for (int c = 0; c < 3; ++c) f(c) = readParameter(LoadForceTarget{load, c}, s.model);
            return f;
          },
          "load"_a, "Total force of a load (N)");

  m.def(
      "load", [](const std::string& path) { return loadScene(path); }, "path"_a,
      "Reads a YAML scene; InputError \"<file>:<line>: <key>: <what was expected>\"");
  m.def(
      "load_string",
      [](const std::string& yaml, const std::string& name, const std::string& dir) {
        return loadSceneFromString(yaml, name, dir);
      },
      "yaml"_a, "source_name"_a = "<string>", "directory"_a = ".",
      "A scene from YAML text; relative paths resolve against `directory`");

  py::class_<SceneSimulation>(m, "Simulation",
                              "A scene's model advanced step by step (positions m, time s)")
      .def(py::init<const Scene&>(), "scene"_a)
      .def("step", &SceneSimulation::step, py::call_guard<py::gil_scoped_release>(),
           "One time step; NumericalError names the step when it fails")
      .def(
          "run",
          [](SceneSimulation& sim, std::optional<int> steps,
             const std::optional<py::function>& callback) {
            const int n = steps.value_or(sim.scene().steps - sim.stepsDone());
            for (int i = 0; i < n; ++i) {
              {
                py::gil_scoped_release release;
                sim.step();
              }
              if (callback) (*callback)(sim);
            }
          },
          "steps"_a = py::none(), "callback"_a = py::none(),
          "Runs `steps` steps (None: to the scene's end), calling callback(simulation) after each")
      .def_property_readonly("step_index", &SceneSimulation::stepsDone)
      .def_property_readonly("time", [](const SceneSimulation& s) { return s.state().t; })
      .def_property_readonly(
          "positions", [](const SceneSimulation& s) { return nodeRows(s.state().x); },
          "#V x 3 node positions, m")
      .def_property_readonly(
          "velocities", [](const SceneSimulation& s) { return nodeRows(s.state().v); },
          "#V x 3 node velocities, m/s")
      .def_property_readonly("model", &SceneSimulation::model,
                             py::return_value_policy::reference_internal)
      .def(
          "markers", [](const SceneSimulation& s) { return s.pointPositions(s.scene().markers); },
          "Marker positions now, m")
      .def(
          "hidden_points",
          [](const SceneSimulation& s) { return s.pointPositions(s.scene().hidden); },
          "Hidden points (tumours) now, m")
      .def(
          "validation_points",
          [](const SceneSimulation& s) { return s.pointPositions(s.scene().validation); },
          "Validation points now, m");

  py::class_<RunProgress>(m, "RunProgress")
      .def_readonly("variant", &RunProgress::variant)
      .def_readonly("step", &RunProgress::step)
      .def_readonly("steps", &RunProgress::steps)
      .def_readonly("elapsed_seconds", &RunProgress::elapsedSeconds)
      .def_readonly("mean_step_ms", &RunProgress::meanStepMs);
  py::class_<AssimilationProgress>(m, "AssimilationProgress")
      .def_readonly("step", &AssimilationProgress::step)
      .def_readonly("steps", &AssimilationProgress::steps)
      .def_readonly("elapsed_seconds", &AssimilationProgress::elapsedSeconds)
      .def_readonly("mean_step_ms", &AssimilationProgress::meanStepMs)
      .def_readonly("free_run", &AssimilationProgress::freeRun)
      .def_readonly("estimate", &AssimilationProgress::estimate);

  py::class_<ParameterResult>(m, "ParameterResult", "An estimated parameter (SI units)")
      .def_readonly("name", &ParameterResult::name)
      .def_readonly("initial_mean", &ParameterResult::initialMean)
      .def_readonly("initial_stddev", &ParameterResult::initialStddev)
      .def_readonly("mean", &ParameterResult::mean)
      .def_readonly("stddev", &ParameterResult::stddev)
      .def_readonly("truth", &ParameterResult::truth)
      .def("__repr__", [](const ParameterResult& p) {
        return "<ParameterResult " + p.name + " " + std::to_string(p.mean) + " +- " +
               std::to_string(p.stddev) + ">";
      });
  py::class_<ErrorResult>(m, "ErrorResult", "Validation errors over steps (m and % of D)")
      .def_readonly("steps", &ErrorResult::steps)
      .def_readonly("mean_m", &ErrorResult::meanM)
      .def_readonly("max_m", &ErrorResult::maxM)
      .def_readonly("mean_percent", &ErrorResult::meanPercent)
      .def_readonly("max_percent", &ErrorResult::maxPercent);
  py::class_<RunErrors>(m, "RunErrors")
      .def_readonly("all", &RunErrors::all)
      .def_readonly("free_run", &RunErrors::freeRun);
  py::class_<AssimilationResult>(m, "AssimilationResult")
      .def_readonly("out_dir", &AssimilationResult::outDir)
      .def_readonly("steps", &AssimilationResult::steps)
      .def_readonly("observed_steps", &AssimilationResult::observedSteps)
      .def_readonly("parameters", &AssimilationResult::parameters)
      .def_readonly("validated", &AssimilationResult::validated)
      .def_readonly("estimated", &AssimilationResult::estimated)
      .def_readonly("initial", &AssimilationResult::initial)
      .def_readonly("median_step_ms", &AssimilationResult::medianStepMs)
      .def_readonly("wall_seconds", &AssimilationResult::wallSeconds)
      .def_readonly("notices", &AssimilationResult::notices);

  m.def(
      "simulate",
      [](const Scene& scene, const std::string& outDir, const std::optional<py::function>& progress,
         bool resume) {
        const auto callback = withGil<RunProgress>(progress);
        SimulationResult r;
        {
          py::gil_scoped_release release;
          r = runSimulation(scene, outDir, callback, resume);
        }
        py::list runs;
        for (const RunResult& run : r.runs) runs.append(runResultDict(run));
        return runs;
      },
      "scene"_a, "out_dir"_a, "progress"_a = py::none(), "resume"_a = false,
      "bcassim simulate: writes the run's files to out_dir, progress(RunProgress) after every "
      "step; returns one dict per run (base, then variants)");
  m.def(
      "assimilate",
      [](const Scene& scene, const std::string& outDir, const std::optional<py::function>& progress,
         bool resume) {
        const auto callback = withGil<AssimilationProgress>(progress);
        AssimilationResult r;
        {
          py::gil_scoped_release release;
          r = runAssimilation(scene, outDir, callback, resume);
        }
        return r;
      },
      "scene"_a, "out_dir"_a, "progress"_a = py::none(), "resume"_a = false,
      "bcassim assimilate: the scene's filter over its tracks, files in out_dir "
      "(estimates.csv, hidden_points.csv, ...), progress(AssimilationProgress) after every step");
  m.def(
      "validate",
      [](const Scene& scene, const std::string& estimates, const std::string& outDir) {
        py::gil_scoped_release release;
        return runValidation(scene, estimates, outDir);
      },
      "scene"_a, "estimates"_a, "out_dir"_a,
      "bcassim validate: a forward run with the last values of estimates.csv against the truth");
}

}  // namespace bcassim::python
