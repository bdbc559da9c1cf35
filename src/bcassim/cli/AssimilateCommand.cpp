// `bcassim assimilate SCENE` (estimate a scene's parameters from observed tracks) and `bcassim
// validate SCENE --estimates FILE` (forward run with the estimates against the truth): the scene
// line, a progress bar, the summary table and validation errors, and the PNG plots. With --mpi
// (under mpirun) rank 0 runs the filter and prints, the other ranks forecast their share.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>

#include "bcassim/Error.h"
#include "bcassim/cli/AssimilationProgressBar.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/distributed/JobEndNotice.h"
#include "bcassim/distributed/MpiForecastDistribution.h"
#include "bcassim/distributed/MpiForecastServer.h"
#include "bcassim/distributed/MpiSession.h"
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
    app.add_flag(
        "--mpi", mpi_,
        "Spread the sigma points over the ranks of an MPI job (mpirun -np N bcassim "
        "assimilate SCENE --mpi): rank 0 runs the filter and prints, every rank "
        "forecasts its share on its --threads; the threaded run's estimates (README, Over MPI "
        "ranks)");
  }

  int run() override {
    if (!mpi_) return runFilter(nullptr, 1);
    const MpiSession session;
    // Once a rank dies mpirun ends the others: rank 0 then says where the run stood, the workers
    // give it the time to.
    if (session.rank() > 0) {
      installWorkerTerminationGrace(kJobEndedExitCode);
      return serveForecasts(session);
    }
    installJobEndNotice(kJobEndedExitCode);
    // Declared before the scene is read: whatever fails on rank 0, its destructor releases the
    // other ranks.
    MpiForecastDistribution distribution(
        session, [this](int step, const std::string& ranks) { return jobEndLine(step, ranks); });
    return runFilter(&distribution, session.size());
  }

 private:
  // Exit code of the ranks mpirun ends when one of them died.
  static constexpr int kJobEndedExitCode = 3;

  // The scene with --threads applied; `threads` says what the forecasts run on.
  Scene loadWithThreads(std::string* threads = nullptr) {
    Scene scene = loadScene(args_.scenePath);
    requireAssimilation(args_.scenePath, scene);
    AssimilationSettings& s = *scene.assimilation;
    if (threads) *threads = fmt::format("{} thread{}", s.threads, s.threads == 1 ? "" : "s");
    if (threads_ > 0) {
      if (threads)
        *threads = fmt::format("{} thread{} (--threads; the scene says {})", threads_,
                               threads_ == 1 ? "" : "s", s.threads);
      s.threads = threads_;
    }
    checkpointEvery_ = scene.output.every;
    return scene;
  }

  // The run with the filter (alone, or rank 0 of `ranks` with `distribution`), printing.
  int runFilter(MpiForecastDistribution* distribution, int ranks) {
    const io::OutputDirectoryLock lock(args_.outDir);
    std::string threads;
    Scene scene = loadWithThreads(&threads);
    if (distribution)
      threads = fmt::format("{} MPI rank{} x {}", ranks, ranks == 1 ? "" : "s", threads);
    printSceneLine(args_.scenePath, scene, threads);
    AssimilationProgressBar bar(stderr);
    AssimilationCallback progress;
    if (!args_.quiet) progress = [&bar](const AssimilationProgress& p) { bar.update(p); };
    const AssimilationResult result =
        runAssimilation(scene, args_.outDir, progress, resume_, nullptr, distribution);
    bar.finish();
    printSummary(result, true);
    if (distribution && distribution->stats().steps > 0) printTransfers(distribution->stats());
    if (!args_.noPlots) plot(args_.outDir);
    return 0;
  }

  // What went between the ranks per step, for the cost model (docs/benchmarks.md §8).
  static void printTransfers(const MpiTransferStats& t) {
    const double n = t.steps;
    fmt::print(
        "MPI: per step {:.4g} MB to the other ranks, {:.4g} MB back; rank 0 {:.3g} ms sending "
        "the sigma points, {:.3g} ms receiving the forecasts (waiting included), {:.3g} ms "
        "sending the mean\n",
        1e-6 * t.sentBytes / n, 1e-6 * t.receivedBytes / n, 1e3 * t.sendSeconds / n,
        1e3 * t.receiveSeconds / n, 1e3 * t.endStepSeconds / n);
    if (t.covarianceSteps > 0) {
      const double k = 1e3 / t.covarianceSteps;
      fmt::print(
          "MPI: covariance kept over the ranks, rank 0 per step after the first: Cholesky {:.3g} "
          "ms "
          "(pdpotrf "
          "{:.3g}), factor's columns {:.3g} ms, own sigma points {:.3g} ms, mean and Gram matrix "
          "{:.3g} ms (products {:.3g}, reduce-scatter {:.3g}), correction {:.3g} ms\n",
          k * t.factorSeconds, k * t.pdpotrfSeconds, k * t.columnsSeconds, k * t.pointsSeconds,
          k * t.gramSeconds, k * t.gramProductSeconds, k * t.gramReduceSeconds,
          k * t.correctSeconds);
    }
  }

  // A worker rank: the same scene and models, silent; its errors go to rank 0, which prints
  // them.
  int serveForecasts(const MpiSession& session) {
    MpiForecastServer server(session);
    std::exception_ptr failed;
    try {
      const Scene scene = loadWithThreads();
      serveAssimilationForecasts(scene, args_.outDir, resume_,
                                 [&server](ForecastEnsemble& e) { server.serve(e); });
      return 0;
    } catch (...) {
      failed = std::current_exception();
    }
    server.fail(failed);
    return 0;
  }

  // The line rank 0 prints when the job is ended during `step` while `ranks` owed forecasts.
  std::string jobEndLine(int step, const std::string& ranks) const {
    if (step == 0)
      return fmt::format(
          "bcassim: error: {}: the MPI job was ended before the first assimilation step (a rank "
          "died, or mpirun was stopped)",
          args_.scenePath);
    const int checkpoint =
        checkpointEvery_ > 0 ? (step - 1) / checkpointEvery_ * checkpointEvery_ : 0;
    const std::string owing =
        ranks.empty() ? std::string()
                      : fmt::format(" while rank{} {} had not answered",
                                    ranks.find(',') == std::string::npos ? "" : "s", ranks);
    return fmt::format(
        "bcassim: error: {}: assimilation step {}: the MPI job was ended{} (a rank died, or "
        "mpirun was stopped); {}",
        args_.scenePath, step, owing,
        checkpoint > 0
            ? fmt::format("the same command with --resume continues from the checkpoint of step {}",
                          checkpoint)
            : std::string("no checkpoint was written yet: run it again without --resume"));
  }

  AssimilationArguments args_;
  bool resume_ = false, mpi_ = false;
  int threads_ = 0;          // 0: not given (--threads itself accepts only >= 1)
  int checkpointEvery_ = 0;  // the scene's output.every, once read
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
