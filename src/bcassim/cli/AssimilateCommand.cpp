// `bcassim assimilate SCENE` (estimate a scene's parameters from observed tracks) and `bcassim
// validate SCENE --estimates FILE` (forward run with the estimates against the truth): the scene
// line, a progress bar, the summary table and validation errors, and the PNG plots.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>

#include "bcassim/Error.h"
#include "bcassim/cli/AssimilationProgressBar.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/io/OutputDirectoryLock.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "bcassim/viz/PlotScripts.h"

namespace bcassim {
namespace {

const char* filterName(FilterKind k) {
  return k == FilterKind::Ukf ? "ukf" : k == FilterKind::Roukf ? "roukf" : "etkf";
}

// Throws an InputError naming the scene when it has no assimilation: section.
void requireAssimilation(const std::string& scenePath, const Scene& scene) {
  if (!scene.assimilation)
    throw InputError(scenePath + ": no assimilation: section (see docs/assimilation-format.md)");
}

// threads: what the sigma points run on, with where the number comes from; empty for validate,
// whose forward runs are serial.
void printSceneLine(const std::string& scenePath, const Scene& scene, const std::string& threads) {
  const AssimilationSettings& s = *scene.assimilation;
  fmt::print(
      "scene {}: {} nodes, {} markers, {} validation points, {} parameter{}, filter {}, "
      "{}{} steps of {:.6g} s, observations until step {}\n",
      scenePath, scene.model.mesh->numNodes(), scene.markers.points.size(),
      scene.validation.points.size(), s.parameters.size(), s.parameters.size() == 1 ? "" : "s",
      filterName(s.filter), threads.empty() ? "" : threads + ", ", scene.steps, scene.dt(),
      std::min(s.observations.untilStep, scene.steps));
  std::fflush(stdout);
}

void printSummary(const AssimilationResult& r, bool assimilated) {
  fmt::print("\n{:<14} {:>24} {:>24} {:>12} {:>10}\n", "parameter", "initial",
             assimilated ? "estimate" : "validated", "truth", "error");
  for (const ParameterResult& p : r.parameters) {
    const std::string truth = p.truth ? fmt::format("{:.6g}", *p.truth) : "-";
    const std::string error = p.truth && *p.truth != 0
                                  ? fmt::format("{:+.2f}%", 100 * (p.mean - *p.truth) / *p.truth)
                                  : "-";
    fmt::print("{:<14} {:>24} {:>24} {:>12} {:>10}\n", p.name,
               fmt::format("{:.6g} ± {:.3g}", p.initialMean, p.initialStddev),
               fmt::format("{:.6g} ± {:.3g}", p.mean, p.stddev), truth, error);
  }
  if (r.validated) {
    fmt::print("\nvalidation error, relative to the truth's max deformation {:.4g} mm:\n",
               1e3 * r.maxDeformationM);
    const auto line = [](const char* name, const ErrorResult& e) {
      if (e.steps == 0) return;
      fmt::print("  {:<22} mean {:7.3f}% ({:.4g} mm)   max {:7.3f}% ({:.4g} mm)   {} steps\n", name,
                 e.meanPercent, 1e3 * e.meanM, e.maxPercent, 1e3 * e.maxM, e.steps);
    };
    line(assimilated ? "estimated" : "final parameters", r.estimated.all);
    line("  free run", r.estimated.freeRun);
    line("initial parameters", r.initial.all);
    line("  free run", r.initial.freeRun);
  } else {
    fmt::print("no validation (assimilation.validation.tracks not given)\n");
  }
  fmt::print("{}: median {:.3g} ms/step (mean {:.3g}), {:.3g} s in all -> {}\n",
             assimilated ? "assimilation" : "validation", r.medianStepMs, r.meanStepMs,
             r.wallSeconds, r.outDir);
}

// PNG plots of an output directory when python3 with matplotlib is there; one line either way.
void plot(const std::string& outDir) {
  const std::string problem = runPlotScript("plot_assimilation.py", {outDir});
  if (!problem.empty()) fmt::print("plots skipped: {}\n", problem);
}

// The arguments and options assimilate and validate share.
struct AssimilationArguments {
  std::string scenePath, outDir = "out";
  bool quiet = false, noPlots = false;

  void declare(CLI::App& app) {
    app.add_option("scene", scenePath, "Scene file with an assimilation: section")->required();
    addOutOption(app, outDir);
    addQuietFlag(app, quiet);
    addNoPlotsFlag(app, noPlots);
  }
};

class AssimilateCommand : public Command {
 public:
  AssimilateCommand()
      : Command({"assimilate"}, "Estimate a scene's parameters from observed tracks") {}

  void declare(CLI::App& app) override {
    args_.declare(app);
    addResumeFlag(app, resume_,
                  "its last checkpoint (written every output.every steps). The same files byte "
                  "for byte as a run that never stopped with reuse_factorization: false, with "
                  "tangent: mean (no tangent_background) and with etkf; with the defaults roukf "
                  "and ukf may differ in a last printed digit, and tangent_background: true "
                  "estimates agreed within 4e-4 relative (README, Resuming)");
    addThreadsOption(app, threads_,
                     "the sigma points' forecasts (default: the scene's assimilation.threads)",
                     false);
  }

  int run() override {
    const io::OutputDirectoryLock lock(args_.outDir);
    Scene scene = loadScene(args_.scenePath);
    requireAssimilation(args_.scenePath, scene);
    AssimilationSettings& s = *scene.assimilation;
    std::string threads = fmt::format("{} thread{}", s.threads, s.threads == 1 ? "" : "s");
    if (threads_ > 0) {
      threads = fmt::format("{} thread{} (--threads; the scene says {})", threads_,
                            threads_ == 1 ? "" : "s", s.threads);
      s.threads = threads_;
    }
    printSceneLine(args_.scenePath, scene, threads);
    AssimilationProgressBar bar(stderr);
    AssimilationCallback progress;
    if (!args_.quiet) progress = [&bar](const AssimilationProgress& p) { bar.update(p); };
    const AssimilationResult result = runAssimilation(scene, args_.outDir, progress, resume_);
    bar.finish();
    printSummary(result, true);
    if (!args_.noPlots) plot(args_.outDir);
    return 0;
  }

 private:
  AssimilationArguments args_;
  bool resume_ = false;
  int threads_ = 0;  // 0: not given (--threads itself accepts only >= 1)
};

class ValidateCommand : public Command {
 public:
  ValidateCommand()
      : Command({"validate"},
                "Forward run with estimated parameters against the truth validation tracks") {}

  void declare(CLI::App& app) override {
    args_.declare(app);
    app.add_option("--estimates", estimatesPath_, "estimates.csv of an assimilate run (last step)")
        ->required();
  }

  int run() override {
    const io::OutputDirectoryLock lock(args_.outDir);
    const Scene scene = loadScene(args_.scenePath);
    requireAssimilation(args_.scenePath, scene);
    if (!scene.assimilation->validationTruth)
      throw InputError(args_.scenePath +
                       ": assimilation.validation.tracks: missing (truth of the validation "
                       "points)");
    printSceneLine(args_.scenePath, scene, "");
    AssimilationProgressBar bar(stderr);
    AssimilationCallback progress;
    if (!args_.quiet) progress = [&bar](const AssimilationProgress& p) { bar.update(p); };
    const AssimilationResult result = runValidation(scene, estimatesPath_, args_.outDir, progress);
    bar.finish();
    printSummary(result, false);
    if (!args_.noPlots) plot(args_.outDir);
    return 0;
  }

 private:
  AssimilationArguments args_;
  std::string estimatesPath_;
};

}  // namespace

std::unique_ptr<Command> makeAssimilateCommand() { return std::make_unique<AssimilateCommand>(); }
std::unique_ptr<Command> makeValidateCommand() { return std::make_unique<ValidateCommand>(); }

}  // namespace bcassim
