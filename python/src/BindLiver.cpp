// bcassim.liver: the liver experiment of thesis chapter 5 end to end (bcassim liver run): meshes,
// ground truth, ROUKF estimation of the ligament springs, validation at inner points, the
// fixed-ligament baseline. The tumour predictions are in <out_dir>/estimate/hidden_points.csv
// (bcassim.io.read_hidden_points gives them as NumPy arrays).
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "bcassim/experiments/liver/LiverPipeline.h"
#include "bcassim/experiments/liver/LiverSurfacePath.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

namespace {
py::dict errorDict(const ErrorOverTime& e) {
  return py::dict("mean_mm"_a = e.meanMm, "mean_std_mm"_a = e.meanStdMm, "max_mm"_a = e.maxMm,
                  "max_std_mm"_a = e.maxStdMm, "peak_mm"_a = e.peakMm, "steps"_a = e.steps);
}
}  // namespace

void bindLiver(py::module_& m) {
  m.def(
      "run",
      [](const std::string& surface, const std::string& outDir, int coarseNodes, int fineNodes,
         int steps, int observedSteps, int markers, int tumours, int groups, double noise,
         double dt, int threads, const std::optional<py::function>& stage) {
        LiverScenarioOptions o;
        o.surface = resolveLiverSurface(surface);
        o.coarseNodes = coarseNodes;
        o.fineNodes = fineNodes;
        o.steps = steps;
        o.observedSteps = observedSteps;
        o.markers = markers;
        o.tumours = tumours;
        o.groups = groups;
        o.noise = noise;
        o.dt = dt;
        o.threads = threads;
        std::shared_ptr<py::function> f;
        if (stage) f = std::make_shared<py::function>(*stage);
        LiverCallbacks callbacks;
        if (f)
          callbacks.stage = [f](const std::string& name) {
            py::gil_scoped_acquire gil;
            (*f)(name);
          };
        LiverReport r;
        {
          py::gil_scoped_release release;
          r = runLiverPipeline(o, outDir, callbacks);
        }
        py::list parameters;
        for (const ParameterResult& p : r.assimilation.parameters)
          parameters.append(py::dict("name"_a = p.name, "initial_mean"_a = p.initialMean,
                                     "mean"_a = p.mean, "stddev"_a = p.stddev,
                                     "truth"_a = p.truth));
        return py::dict("out_dir"_a = outDir, "estimated"_a = errorDict(r.estimated),
                        "prior"_a = errorDict(r.prior), "fixed"_a = errorDict(r.fixed),
                        "max_deformation_mm"_a = r.maxDeformationMm,
                        "tumour_radius95_mm"_a = r.finalTumourRadius95Mm,
                        "tumour_coverage"_a = r.tumourCoverage,
                        "median_step_ms"_a = r.assimilation.medianStepMs,
                        "parameters"_a = parameters);
      },
      "surface"_a = "phantom", "out_dir"_a = "out/liver", "coarse_nodes"_a = 2150,
      "fine_nodes"_a = 14000, "steps"_a = 400, "observed_steps"_a = 300, "markers"_a = 14,
      "tumours"_a = 3, "groups"_a = 10, "noise"_a = 5e-4, "dt"_a = 0.02, "threads"_a = 2,
      "stage"_a = py::none(),
      "surface: 'phantom', a shared liver's name (e.g. 'liver-3') or a closed surface file in "
      "mm; noise in m, dt in s. Returns the inner-point errors (mm) of the estimate, the prior "
      "and the fixed-ligament baseline, the tumours' 95 % radius and coverage, the parameters; "
      "stage(name) is called as each stage starts");
}

}  // namespace bcassim::python
