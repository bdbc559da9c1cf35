// `bcassim liver prepare|run SURFACE`: the liver experiment of thesis §5.1 from one annotated CT
// surface: the scenario files only, or the whole run with a summary table, plots and a picture.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>

#include "bcassim/VectorFormat.h"
#include "bcassim/cli/AssimilationProgressBar.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/ProgressBar.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/experiments/liver/LiverPipeline.h"
#include "bcassim/experiments/liver/LiverSurfacePath.h"
#include "bcassim/io/OutputDirectoryLock.h"
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

void printReport(const LiverReport& r, const LiverScenarioOptions& o, const std::string& outDir) {
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
  fmt::print("results: {}/summary.csv, errors_over_time.csv, */simulation.pvd\n", outDir);
}

// The surface and the scenario's options, the same for prepare and run.
struct LiverArguments {
  std::string surface, outDir = "out/liver";
  LiverScenarioOptions options;

  void declare(CLI::App& app) {
    LiverScenarioOptions& o = options;
    app.add_option("surface", surface,
                   "Liver surface with a .eseg beside it, a name in $BCASSIM_DATA/livers "
                   "(e.g. LiTS-3), or 'phantom' (built in)")
        ->required();
    addOutOption(app, outDir);
    addScaleOption(app, o.scale);
    app.add_option("--coarse-nodes", o.coarseNodes, "Estimation mesh nodes")->capture_default_str();
    app.add_option("--fine-nodes", o.fineNodes, "Ground-truth mesh nodes")->capture_default_str();
    app.add_option("--groups", o.groups, "Spring groups estimated (K)")->capture_default_str();
    app.add_option("--dt", o.dt, "Time step (s)")->capture_default_str();
    app.add_option("--steps", o.steps, "Time steps")->capture_default_str();
    app.add_option("--observed-steps", o.observedSteps, "Steps with observations, then free run")
        ->capture_default_str();
    app.add_option("--noise", o.noise, "Observation noise standard deviation (m)")
        ->capture_default_str();
    app.add_option("--ligament-stiffness", o.ligamentStiffness,
                   "Truth ligament stiffness per metre of curve (N/m per m)")
        ->capture_default_str();
    app.add_option("--right-force", o.rightLobeForce,
                   "Peak downward force on the right lobe (N; 0: from --lobe-displacement)")
        ->capture_default_str();
    app.add_option("--left-force", o.leftLobeForce,
                   "Peak up/down force on the left lobe (N; 0: from --lobe-displacement)")
        ->capture_default_str();
    app.add_option("--lobe-displacement", o.lobeDisplacement,
                   "Static displacement of each lobe without ligament that sizes the loads (m)")
        ->capture_default_str();
    addThreadsOption(app, o.threads,
                     "the sigma points' forecasts (assimilation.threads of estimate.yaml)", true);
  }

  // The options with the surface resolved to a file (or the phantom).
  LiverScenarioOptions resolved() const {
    LiverScenarioOptions o = options;
    o.surface = resolveLiverSurface(surface);
    return o;
  }
};

class LiverPrepareCommand : public Command {
 public:
  LiverPrepareCommand()
      : Command({"liver", "prepare"},
                "Mesh an annotated liver and write the truth, estimation and baseline scenes") {}

  void declare(CLI::App& app) override { args_.declare(app); }

  int run() override {
    const LiverScenarioOptions o = args_.resolved();
    fmt::print("liver {}\n", o.surface);
    std::fflush(stdout);
    printScenario(prepareLiverScenario(o, args_.outDir));
    fmt::print(
        "next: cd {0} && bcassim simulate truth.yaml --out truth && bcassim assimilate "
        "estimate.yaml --out estimate && bcassim simulate baseline.yaml --out baseline\n",
        args_.outDir);
    return 0;
  }

 private:
  LiverArguments args_;
};

class LiverRunCommand : public Command {
 public:
  LiverRunCommand()
      : Command({"liver", "run"},
                "Prepare, run the truth, estimate the ligament, validate against a fixed "
                "baseline") {}

  void declare(CLI::App& app) override {
    args_.declare(app);
    addQuietFlag(app, quiet_);
    addNoPlotsFlag(app, noPlots_);
    app.add_flag("--no-picture", noPicture_, "Do not render the liver picture");
    addResumeFlag(app, resume_,
                  "the checkpoints of its ground-truth, prior and baseline runs (the "
                  "assimilation is redone)");
  }

  int run() override {
    const LiverScenarioOptions o = args_.resolved();
    const std::string& outDir = args_.outDir;
    const io::OutputDirectoryLock lock(outDir);
    fmt::print("liver {} -> {}\n", o.surface, outDir);
    std::fflush(stdout);
    ProgressBar simBar(stderr);
    AssimilationProgressBar assimBar(stderr);
    LiverCallbacks cb;
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
    const LiverReport r = runLiverPipeline(o, outDir, cb, resume_);
    simBar.finish();
    assimBar.finish();
    printReport(r, o, outDir);
    if (!noPlots_) plot(outDir);
    if (!noPicture_) picture(outDir);
    return 0;
  }

 private:
  static void plot(const std::string& outDir) {
    for (const auto& [script, dir] :
         {std::pair<std::string, std::string>{
              "plot_assimilation.py", (std::filesystem::path(outDir) / "estimate").string()},
          {"plot_liver.py", outDir}}) {
      const std::string problem = runPlotScript(script, {dir});
      if (!problem.empty()) fmt::print("plots skipped: {}\n", problem);
    }
  }

  static void picture(const std::string& outDir) {
    std::fflush(stdout);
    const std::string path = (std::filesystem::path(outDir) / "liver.png").string();
    const std::string problem = renderLiverPicture(outDir, path);
    if (problem.empty())
      fmt::print("picture: {}\n", path);
    else
      fmt::print("picture skipped: {}\n", problem);
  }

  LiverArguments args_;
  bool quiet_ = false, noPlots_ = false, noPicture_ = false, resume_ = false;
};

}  // namespace

std::unique_ptr<Command> makeLiverPrepareCommand() {
  return std::make_unique<LiverPrepareCommand>();
}
std::unique_ptr<Command> makeLiverRunCommand() { return std::make_unique<LiverRunCommand>(); }

}  // namespace bcassim
