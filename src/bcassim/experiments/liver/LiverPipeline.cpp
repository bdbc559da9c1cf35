#include "bcassim/experiments/liver/LiverPipeline.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/experiments/liver/ErrorsOverTime.h"
#include "bcassim/experiments/liver/LiverScenes.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/Files.h"
#include "bcassim/scene/ModelParameter.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// Mean of a 95 % radius column of hidden_points.csv over the tumours at a step, mm.
double meanRadiusAt(const CsvTable& t, int step, const std::string& column) {
  const int cs = t.column("step"), cr = t.column(column);
  double sum = 0;
  int n = 0;
  for (Eigen::Index r = 0; r < t.rows.rows(); ++r)
    if (static_cast<int>(t.rows(r, cs)) == step) sum += t.rows(r, cr), ++n;
  return n ? 1e3 * sum / n : 0.0;
}

// Fraction of (tumour, step >= 1) whose predicted position lies within its total 95 % radius of
// the truth; -1 without truth.
double tumourCoverage(const CsvTable& t, const fs::path& truthPath) {
  if (!fs::exists(truthPath)) return -1;
  const MarkerTracks truth = readMarkerTracks(truthPath.string());
  const int cs = t.column("step"), cp = t.column("point"), cx = t.column("x_m"),
            cr = t.column("radius95_total_m");
  int inside = 0, n = 0;
  for (Eigen::Index r = 0; r < t.rows.rows(); ++r) {
    const auto step = static_cast<size_t>(t.rows(r, cs));
    const auto point = static_cast<Eigen::Index>(t.rows(r, cp));
    if (step < 1 || step >= truth.frames.size() || point >= truth.frames[step].rows()) continue;
    const Vec3 predicted = t.rows.block<1, 3>(r, cx).transpose();
    const Vec3 actual = truth.frames[step].row(point).transpose();
    if (!actual.allFinite()) continue;
    ++n;
    if ((predicted - actual).norm() <= t.rows(r, cr)) ++inside;
  }
  return n ? static_cast<double>(inside) / n : -1;
}

}  // namespace

LiverReport runLiverPipeline(const LiverScenarioOptions& options, const std::string& outDir,
                             const LiverCallbacks& cb, bool resume) {
  const fs::path dir(outDir);
  // Forward runs that do not depend on the estimates continue from their checkpoints.
  auto resumable = [&](const char* run) {
    return resume && fs::exists(dir / run / "checkpoint.bin");
  };
  auto stage = [&](const std::string& s) {
    if (cb.stage) cb.stage(s);
  };
  LiverReport report;
  stage("prepare");
  report.scenario = prepareLiverScenario(options, outDir, cb.log);

  const LiverScenario& scenario = report.scenario;

  // The scenes built in code; the .yaml files beside them are for the user only.
  stage("truth");
  report.truth = runSimulation(*scenario.truthScene, (dir / "truth").string(), cb.simulation,
                               resumable("truth"));

  stage("estimate");
  const Scene estimate = withTruthTracks(*scenario.estimateScene, (dir / "truth").string());
  report.assimilation = runAssimilation(estimate, (dir / "estimate").string(), cb.assimilation);

  // Validation (thesis §5.1): forward runs from rest of the coarse model with the final
  // estimates and with the prior, compared with the truth like the baseline.
  stage("validate");
  Scene estimated = *scenario.estimateScene;
  for (size_t i = 0; i < report.assimilation.parameters.size(); ++i)
    applyParameter(estimated.assimilation->parameters[i].target,
                   report.assimilation.parameters[i].mean, estimated.model);
  estimated.assimilation.reset();
  report.estimatedRun = runSimulation(estimated, (dir / "estimated").string(), cb.simulation);
  Scene prior = *scenario.estimateScene;
  prior.assimilation.reset();
  prior.output.pvd = false;
  report.priorRun =
      runSimulation(prior, (dir / "prior").string(), cb.simulation, resumable("prior"));

  stage("baseline");
  report.baseline = runSimulation(*scenario.baselineScene, (dir / "baseline").string(),
                                  cb.simulation, resumable("baseline"));

  const fs::path truthTracks = dir / "truth" / "validation.csv";
  const StepSeries est =
      validationErrorSeries((dir / "estimated" / "validation.csv").string(), truthTracks.string());
  const StepSeries pri =
      validationErrorSeries((dir / "prior" / "validation.csv").string(), truthTracks.string());
  const StepSeries fixed =
      validationErrorSeries((dir / "baseline" / "validation.csv").string(), truthTracks.string());
  report.estimated = summariseErrors(est);
  report.prior = summariseErrors(pri);
  report.fixed = summariseErrors(fixed);
  {
    const MarkerTracks t = readMarkerTracks(truthTracks.string());
    for (const Eigen::MatrixX3d& f : t.frames)
      report.maxDeformationMm = std::max(report.maxDeformationMm,
                                         1e3 * (f - t.frames.front()).rowwise().norm().maxCoeff());
  }

  const fs::path hidden = dir / "estimate" / "hidden_points.csv";
  if (fs::exists(hidden)) {
    const CsvTable t = readCsvTable(hidden.string());
    report.initialTumourRadius95Mm = meanRadiusAt(t, 1, "radius95_m");
    report.finalTumourRadius95Mm = meanRadiusAt(t, options.steps, "radius95_m");
    report.finalTumourTotalRadius95Mm = meanRadiusAt(t, options.steps, "radius95_total_m");
    report.tumourCoverage = tumourCoverage(t, dir / "truth" / "hidden.csv");
  }

  {
    std::ofstream out(dir / "errors_over_time.csv");
    out << "step,time_s,estimated_mean_mm,estimated_max_mm,prior_mean_mm,prior_max_mm,"
           "fixed_mean_mm,fixed_max_mm\n";
    const size_t n = std::min({est.mean.size(), pri.mean.size(), fixed.mean.size()});
    for (size_t k = 0; k < n; ++k)
      out << fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", k + 1,
                         (k + 1) * options.dt, est.mean[k], est.max[k], pri.mean[k], pri.max[k],
                         fixed.mean[k], fixed.max[k]);
    if (!out) io::throwWriteError((dir / "errors_over_time.csv").string());
  }
  {
    std::ofstream out(dir / "summary.csv");
    out << "model,mean_error_mm,mean_error_std_mm,max_error_mm,max_error_std_mm,peak_error_mm\n";
    for (const auto& [name, e] :
         {std::pair<const char*, const ErrorOverTime*>{"estimated", &report.estimated},
          {"prior", &report.prior},
          {"fixed", &report.fixed}})
      out << fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", name, e->meanMm, e->meanStdMm,
                         e->maxMm, e->maxStdMm, e->peakMm);
    out << fmt::format(
        "# assimilation median step {:.6g} ms, dt {:.6g} s, truth max deformation {:.6g} mm\n",
        report.assimilation.medianStepMs, options.dt, report.maxDeformationMm);
    if (report.tumourCoverage >= 0)
      out << fmt::format(
          "# tumours: final 95 % radius {:.6g} mm (with model error), coverage {:.6g}\n",
          report.finalTumourTotalRadius95Mm, report.tumourCoverage);
    const LiverAtlasSprings& atlas = report.scenario.atlas;
    if (atlas.used)
      out << fmt::format(
          "# atlas mode: springs on the {} of {}; distance from the expert's curve mean "
          "{} mm, max {} mm\n",
          atlas.band ? "edges of the band" : "mean curve", atlas.source,
          atlas.expertDistanceMean >= 0 ? fmt::format("{:.6g}", 1e3 * atlas.expertDistanceMean)
                                        : "undefined",
          atlas.expertDistanceMax >= 0 ? fmt::format("{:.6g}", 1e3 * atlas.expertDistanceMax)
                                       : "undefined");
  }
  return report;
}

}  // namespace bcassim
