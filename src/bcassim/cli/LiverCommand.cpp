#include "bcassim/cli/LiverCommand.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/VectorFormat.h"
#include "bcassim/cli/AssimilationProgressBar.h"
#include "bcassim/cli/ProgressBar.h"
#include "bcassim/experiments/liver/LiverPipeline.h"
#include "bcassim/experiments/liver/LiverSurfacePath.h"
#include "bcassim/viz/LiverPicture.h"
#include "bcassim/viz/PlotScripts.h"

namespace bcassim {
namespace {

void printScenario(const LiverScenario& s) {
  fmt::print(
      "meshes: estimation {} nodes / {} tets, truth {} nodes / {} tets ({:.1f} s + {:.1f} s)\n",
      s.coarse.outputNodes, s.coarse.outputTets, s.fine.outputNodes, s.fine.outputTets,
      s.coarse.seconds, s.fine.seconds);
  fmt::print("falciform curve {:.1f} mm; frame: lateral {} anterior {} superior {}{}\n",
             1e3 * s.curveLength, formatVec3(s.anatomy.lateral, 3),
             formatVec3(s.anatomy.anterior, 3), formatVec3(s.anatomy.superior, 3),
             s.anatomy.ridgeFound ? "" : " (no ridge label: superior guessed)");
  fmt::print(
      "loads: right lobe {:.3g} N down, left lobe {:.3g} N up/down; baseline: {} nodes fixed "
      "along the ligament; scenes in {}\n",
      s.rightForce, s.leftForce, s.fixedNodes, s.dir);
  std::fflush(stdout);
}

}  // namespace

LiverCommand::LiverCommand(CLI::App& app) {
  liver_ = app.add_subcommand("liver", "The liver experiment of thesis §5.1 from a CT surface");
  liver_->require_subcommand(1);
  prepare_ = liver_->add_subcommand(
      "prepare", "Mesh an annotated liver and write the truth, estimation and baseline scenes");
  run_ = liver_->add_subcommand(
      "run", "Prepare, run the truth, estimate the ligament, validate against a fixed baseline");
  LiverScenarioOptions& o = options_;
  for (CLI::App* c : {prepare_, run_}) {
    c->add_option("surface", surface_,
                  "Liver surface with a .eseg beside it, a name in $BCASSIM_DATA/livers "
                  "(e.g. LiTS-3), or 'phantom' (built in)")
        ->required();
    c->add_option("-o,--out", outDir_, "Output directory")->capture_default_str();
    c->add_option("--scale", o.scale, "Metres per surface unit (1e-3 for mm)")
        ->capture_default_str();
    c->add_option("--coarse-nodes", o.coarseNodes, "Estimation mesh nodes")->capture_default_str();
    c->add_option("--fine-nodes", o.fineNodes, "Ground-truth mesh nodes")->capture_default_str();
    c->add_option("--groups", o.groups, "Spring groups estimated (K)")->capture_default_str();
    c->add_option("--dt", o.dt, "Time step, s")->capture_default_str();
    c->add_option("--steps", o.steps, "Time steps")->capture_default_str();
    c->add_option("--observed-steps", o.observedSteps, "Steps with observations, then free run")
        ->capture_default_str();
    c->add_option("--noise", o.noise, "Observation noise standard deviation, m")
        ->capture_default_str();
    c->add_option("--ligament-stiffness", o.ligamentStiffness,
                  "Truth ligament stiffness per metre of curve, N/m per m")
        ->capture_default_str();
    c->add_option("--right-force", o.rightLobeForce,
                  "Peak downward force on the right lobe, N (0: from --lobe-displacement)")
        ->capture_default_str();
    c->add_option("--left-force", o.leftLobeForce,
                  "Peak up/down force on the left lobe, N (0: from --lobe-displacement)")
        ->capture_default_str();
    c->add_option("--lobe-displacement", o.lobeDisplacement,
                  "Static displacement of each lobe without ligament that sizes the loads, m")
        ->capture_default_str();
    c->add_option("--threads", o.threads, "Sigma points run on this many threads")
        ->capture_default_str();
  }
  run_->add_flag("-q,--quiet", quiet_, "No progress bars");
  run_->add_flag("--no-plots", noPlots_, "Do not draw the PNG plots");
  run_->add_flag("--no-picture", noPicture_, "Do not render the liver picture");
  run_->add_flag("--resume", resume_,
                 "Continue a stopped run in --out: the ground truth, prior and baseline runs go on "
                 "from their checkpoints");
}

int LiverCommand::run() const {
  if (prepare_->parsed()) return prepare();
  return runAll();
}

int LiverCommand::prepare() const {
  LiverScenarioOptions o = options_;
  o.surface = resolveLiverSurface(surface_);
  fmt::print("liver {}\n", o.surface);
  std::fflush(stdout);
  printScenario(prepareLiverScenario(o, outDir_));
  fmt::print(
      "next: cd {0} && bcassim simulate truth.yaml --out truth && bcassim assimilate "
      "estimate.yaml --out estimate && bcassim simulate baseline.yaml --out baseline\n",
      outDir_);
  return 0;
}

int LiverCommand::runAll() const {
  LiverScenarioOptions o = options_;
  o.surface = resolveLiverSurface(surface_);
  fmt::print("liver {} -> {}\n", o.surface, outDir_);
  std::fflush(stdout);
  ProgressBar simBar(stderr);
  AssimilationProgressBar assimBar(stderr);
  LiverCallbacks cb;
  std::string current;
  cb.stage = [&](const std::string& s) {
    simBar.finish();
    assimBar.finish();
    static const std::map<std::string, std::string> what = {
        {"prepare", "meshing and scenario"},
        {"truth", "ground truth (fine Ogden liver, dense ligament)"},
        {"estimate", "assimilation (ROUKF, coarse StVK liver, spring groups)"},
        {"validate", "forward run with the estimated ligament (and with the prior)"},
        {"baseline", "baseline: ligament as fixed nodes"}};
    fmt::print("== {}\n", what.at(s));
    std::fflush(stdout);
  };
  if (!quiet_) {
    cb.simulation = [&](const RunProgress& p) { simBar.update(p); };
    cb.assimilation = [&](const AssimilationProgress& p) { assimBar.update(p); };
  }
  const LiverReport r = runLiverPipeline(o, outDir_, cb, resume_);
  simBar.finish();
  assimBar.finish();
  printScenario(r.scenario);

  fmt::print("\n{:<12} {:>22}   (prior {:.4g} ± {:.3g})\n", "parameter", "estimate ± σ",
             r.assimilation.parameters.empty() ? 0.0 : r.assimilation.parameters[0].initialMean,
             r.assimilation.parameters.empty() ? 0.0 : r.assimilation.parameters[0].initialStddev);
  for (const ParameterResult& p : r.assimilation.parameters)
    fmt::print("{:<12} {:>22}\n", p.name, fmt::format("{:.4g} ± {:.3g} N/m", p.mean, p.stddev));

  fmt::print("\ninner validation error over {} steps (truth max deformation {:.1f} mm):\n",
             r.estimated.steps, r.maxDeformationMm);
  fmt::print("  {:<28} {:>18} {:>18} {:>10}\n", "model", "mean ± σ (mm)", "max ± σ (mm)", "peak");
  const auto row = [](const char* name, const ErrorOverTime& e) {
    fmt::print("  {:<28} {:>18} {:>18} {:>10.2f}\n", name,
               fmt::format("{:.2f} ± {:.2f}", e.meanMm, e.meanStdMm),
               fmt::format("{:.2f} ± {:.2f}", e.maxMm, e.maxStdMm), e.peakMm);
  };
  row("estimated springs", r.estimated);
  row("prior springs", r.prior);
  row("fixed ligament (baseline)", r.fixed);
  fmt::print("  thesis §5.1: estimated 2.1 ± 0.9 / 3.2 ± 1.6 mm, fixed 5.9 ± 3.6 / 9.9 ± 6.3 mm\n");
  if (r.initialTumourRadius95Mm > 0 || r.finalTumourTotalRadius95Mm > 0)
    fmt::print(
        "tumours: 95 % radius from the parameters' uncertainty {:.3f} mm after the first "
        "step, {:.3f} mm at the end; with the model error seen in the innovations {:.2f} mm "
        "at the end, which holds the true tumour in {:.0f} % of the steps\n",
        r.initialTumourRadius95Mm, r.finalTumourRadius95Mm, r.finalTumourTotalRadius95Mm,
        100 * r.tumourCoverage);
  const double ms = r.assimilation.medianStepMs;
  fmt::print(
      "assimilation: {} sigma points, median {:.1f} ms/step, real-time factor {:.2f} "
      "(dt {:.0f} ms; ≥ 1 is faster than real time), {:.0f} s in all\n",
      r.assimilation.parameters.size() + 1, ms, 1e3 * o.dt / ms, 1e3 * o.dt,
      r.assimilation.wallSeconds);
  fmt::print("results: {}/summary.csv, errors_over_time.csv, */simulation.pvd\n", outDir_);

  if (!noPlots_) {
    for (const auto& [script, dir] :
         {std::pair<std::string, std::string>{
              "plot_assimilation.py", (std::filesystem::path(outDir_) / "estimate").string()},
          {"plot_liver.py", outDir_}}) {
      const std::string problem = runPlotScript(script, {dir});
      if (!problem.empty()) fmt::print("plots skipped: {}\n", problem);
    }
  }
  if (!noPicture_) {
    std::fflush(stdout);
    const std::string picture = (std::filesystem::path(outDir_) / "liver.png").string();
    const std::string problem = renderLiverPicture(outDir_, picture);
    if (problem.empty())
      fmt::print("picture: {}\n", picture);
    else
      fmt::print("picture skipped: {}\n", problem);
  }
  return 0;
}

}  // namespace bcassim
