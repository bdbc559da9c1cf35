// `bcassim liver prepare|run|tracked SURFACE`: the liver experiment of thesis §5.1 from one
// annotated CT surface (the scenario files only, or the whole run with a summary table, plots and
// a picture), and §5.3's with synthetic tracked tackers (pipeline-tracked).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
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
#include "bcassim/experiments/tracked/TrackedLiverPipeline.h"
#include "bcassim/io/OutputDirectoryLock.h"
#include "bcassim/scene/AssimilationSettings.h"
#include "bcassim/viz/LiverPicture.h"
#include "bcassim/viz/PlotScripts.h"

namespace bcassim {
namespace {

void printScenario(const LiverScenario& s) {
  fmt::print(
      "meshes: estimation {} nodes / {} tets, truth {} nodes / {} tets ({:.1f} s + {:.1f} s)\n",
      s.coarse.outputNodes, s.coarse.outputTets, s.fine.outputNodes, s.fine.outputTets,
      s.coarse.seconds, s.fine.seconds);
  if (s.coarse.insideTestDomain || s.fine.insideTestDomain) {
    const SurfaceMeshingReport& r = s.coarse.insideTestDomain ? s.coarse : s.fine;
    fmt::print(
        "meshes: the repaired surface was not usable ({}); meshed from the surface's ray-vote "
        "inside test instead (boundary within {:.2f} mm of the input surface)\n",
        r.repairProblem, 1e3 * std::max(s.coarse.boundaryDeviation, s.fine.boundaryDeviation));
  }
  fmt::print("falciform curve {:.1f} mm; frame: lateral {} anterior {} superior {}{}\n",
             1e3 * s.curveLength, formatVec3(s.anatomy.lateral, 3),
             formatVec3(s.anatomy.anterior, 3), formatVec3(s.anatomy.superior, 3),
             s.anatomy.ridgeFound ? "" : " (no ridge label: superior guessed)");
  fmt::print(
      "loads: right lobe {:.3g} N down, left lobe {:.3g} N up/down; baseline: {} nodes fixed "
      "along the ligament; scenes in {}\n",
      s.rightForce, s.leftForce, s.fixedNodes, s.dir);
  fmt::print("estimation prior of each spring group: k_gamma {:.4g} ± {:.3g} N/m per spring\n",
             s.priorStiffness, s.priorStddev);
  if (s.atlas.used) {
    fmt::print(
        "atlas mode: estimation springs on the {} of {} (template turned {:.1f} deg; band σ "
        "{:.1f} mm mean; transfer {:.0f} s{})\n",
        s.atlas.band ? "edges of the ±σ band" : "mean curve", s.atlas.source,
        s.atlas.rotationDegrees, 1e3 * s.atlas.meanSigma, s.atlas.transferSeconds,
        s.atlas.buildSeconds > 0 ? fmt::format(", build {:.0f} s", s.atlas.buildSeconds) : "");
    if (s.annotated)
      fmt::print("  its distance from the expert's curve: mean {:.1f} mm, max {:.1f} mm\n",
                 1e3 * s.atlas.expertDistanceMean, 1e3 * s.atlas.expertDistanceMax);
    else
      fmt::print(
          "  no annotation: the truth's ligament follows the atlas curve too (distance "
          "undefined)\n");
  }
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
  std::string threadsWhat = "the sigma points' forecasts (assimilation.threads of estimate.yaml)";

  void declare(CLI::App& app) {
    LiverScenarioOptions& o = options;
    app.add_option("surface", surface,
                   "Liver surface with a .eseg beside it (or none, with --atlas), a name in "
                   "$BCASSIM_DATA/livers (e.g. LiTS-3), or 'phantom' (built in)")
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
    app.add_option("--spring-priors", o.springPriors,
                   "Priors of the estimated springs from a measured tissue: springs.yaml of "
                   "`bcassim ligament springs` (per metre of width, N/m; default: 0.4 times the "
                   "truth's mean)");
    checkNonNegative(
        app.add_option("--prior-spread", o.priorSpread,
                       "How far a patient's ligament may be from the prior, relative to its "
                       "mean: the prior's standard deviation (combined with the calibration's)"))
        ->capture_default_str();
    checkNonNegative(
        app.add_option("--stiffness-walk", o.stiffnessRandomWalk,
                       "Random walk of each estimated stiffness, relative (log space, 1/s^0.5; "
                       "0: constant)"))
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
    addThreadsOption(app, o.threads, threadsWhat, true);
  }

  // Atlas mode, for prepare and run (tracked has its own atlas options).
  void declareAtlas(CLI::App& app) {
    app.add_option("--atlas", options.atlas,
                   "Atlas mode: the estimation's springs on the falciform curve of this ligament "
                   "atlas (a folder of `bcassim atlas build`) transferred onto the liver, not on "
                   "its annotation; the liver needs no .eseg. With --atlas-livers: where the "
                   "atlas built without this liver is kept (default OUT/atlas)");
    app.add_option("--atlas-livers", options.atlasLivers,
                   "Atlas mode: build the atlas from these annotated livers (a folder of .obj + "
                   ".eseg), this liver left out (minutes; kept in --atlas)");
    app.add_flag("--atlas-band", options.atlasBand,
                 "Atlas mode: the two layers of estimation springs on the edges of the atlas' "
                 "band (its mean curve -/+ sigma on this liver, m) instead of +-4 mm about the "
                 "mean curve (the default, without this flag); the baseline's fixed nodes stay "
                 "on the mean curve");
  }

  // The options with the surface resolved to a file (or the phantom).
  LiverScenarioOptions resolved() const {
    LiverScenarioOptions o = options;
    o.surface = resolveLiverSurface(surface);
    return o;
  }
};

// What a liver command shows while its pipeline runs: a "== stage" line named from the
// command's own list, progress bars for the simulations and the assimilation unless quiet, and
// the pipeline's log lines indented under their stage.
class LiverStageDisplay {
 public:
  LiverStageDisplay(std::map<std::string, std::string> stageNames, bool quiet)
      : stageNames_(std::move(stageNames)), quiet_(quiet) {}

  LiverCallbacks callbacks() {
    LiverCallbacks cb;
    cb.stage = [this](const std::string& s) {
      finish();
      const auto it = stageNames_.find(s);
      fmt::print("== {}\n", it == stageNames_.end() ? s : it->second);
      std::fflush(stdout);
    };
    cb.log = [](const std::string& line) {
      fmt::print("   {}\n", line);
      std::fflush(stdout);
    };
    if (!quiet_) {
      cb.simulation = [this](const RunProgress& p) { simBar_.update(p); };
      cb.assimilation = [this](const AssimilationProgress& p) { assimBar_.update(p); };
    }
    return cb;
  }

  void finish() {
    simBar_.finish();
    assimBar_.finish();
  }

 private:
  std::map<std::string, std::string> stageNames_;
  bool quiet_;
  ProgressBar simBar_{stderr};
  AssimilationProgressBar assimBar_{stderr};
};

class LiverPrepareCommand : public Command {
 public:
  LiverPrepareCommand()
      : Command({"liver", "prepare"},
                "Mesh an annotated liver and write the truth, estimation and baseline scenes") {}

  void declare(CLI::App& app) override {
    args_.declare(app);
    args_.declareAtlas(app);
  }

  int run() override {
    const LiverScenarioOptions o = args_.resolved();
    fmt::print("liver {}\n", o.surface);
    std::fflush(stdout);
    printScenario(prepareLiverScenario(o, args_.outDir, [](const std::string& line) {
      fmt::print("  {}\n", line);
      std::fflush(stdout);
    }));
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
    args_.declareAtlas(app);
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
    LiverStageDisplay display(
        {{"prepare", "meshing and scenario"},
         {"truth", "ground truth (fine Ogden liver, dense ligament)"},
         {"estimate", "assimilation (ROUKF, coarse StVK liver, spring groups)"},
         {"validate", "forward run with the estimated ligament (and with the prior)"},
         {"baseline", "baseline: ligament as fixed nodes"}},
        quiet_);
    const LiverCallbacks cb = display.callbacks();
    const LiverReport r = runLiverPipeline(o, outDir, cb, resume_);
    display.finish();
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

void printTrackedReport(const TrackedLiverReport& r, const std::string& outDir) {
  printScenario(r.scenario);
  if (r.atlasUsed)
    fmt::print(
        "springs' curve: atlas of {} without this liver, {:.1f} mm mean ({:.1f} max) from the "
        "expert curve; build {:.0f} s, transfer {:.1f} s\n",
        r.atlas.fromCache ? std::string("the cache")
                          : fmt::format("{} livers", r.atlas.atlasLivers),
        1e3 * r.curveDistanceMean, 1e3 * r.curveDistanceMax, r.atlas.buildSeconds,
        r.atlas.transferSeconds);
  else
    fmt::print("springs' curve: the liver's own labelled curve (no atlas)\n");
  const TrackingScore& t = r.tracking;
  if (r.surface) {
    fmt::print(
        "camera: partial surface, {:.0f} % of the area seen, {} points over the frames ({} "
        "outliers), no correspondences\n",
        100 * r.surfaceAreaFraction, r.cloudPoints, r.cloudOutliers);
    fmt::print(
        "registration (trimmed ICP, {} points of the first frames): rms {:.2f} mm, overlap {:.0f} "
        "%, {} iterations{}; error {:.2f} mm mean, {:.2f} mm max, {:.2f} deg\n",
        r.registeredPoints, 1e3 * r.registration.rms, 100 * r.registration.overlap,
        r.registration.iterations,
        r.registration.converged ? ""
                                 : fmt::format(" (not converged: the last moved {:.2g} mm)",
                                               1e3 * r.registration.lastMove),
        1e3 * r.registrationErrorMean, 1e3 * r.registrationErrorMax, r.registrationAngleDegrees);
  } else {
    fmt::print(
        "camera: {} detections ({} spurious) of {} tackers; tracking: {} tracks, {} identity "
        "switches, {} wrong labels, {} spurious labelled, {} tacker detections unlabelled\n",
        r.detections, r.spuriousDetections, r.tackers, t.tracks, t.identitySwitches, t.wrongLabels,
        t.spuriousLabelled, t.unlabelled);
    fmt::print(
        "  the other assignment method on the same frames: {} tracks, {} switches, {} wrong "
        "labels\n",
        r.otherMethod.tracks, r.otherMethod.identitySwitches, r.otherMethod.wrongLabels);
    fmt::print(
        "registration (ICP, {} markers): rms {:.2f} mm, overlap {:.0f} %, {} iterations{}; error "
        "{:.2f} mm mean, {:.2f} mm max, {:.2f} deg; markers {:.2f} mm from their tackers\n",
        r.markers, 1e3 * r.registration.rms, 100 * r.registration.overlap,
        r.registration.iterations,
        r.registration.converged ? ""
                                 : fmt::format(" (not converged: the last moved {:.2g} mm)",
                                               1e3 * r.registration.lastMove),
        1e3 * r.registrationErrorMean, 1e3 * r.registrationErrorMax, r.registrationAngleDegrees,
        1e3 * r.markerOffsetMean);
  }
  fmt::print("\n{:<12} {:>22}   (prior {:.4g} ± {:.3g})\n", "parameter", "estimate ± σ",
             r.assimilation.parameters.empty() ? 0.0 : r.assimilation.parameters[0].initialMean,
             r.assimilation.parameters.empty() ? 0.0 : r.assimilation.parameters[0].initialStddev);
  for (const ParameterResult& p : r.assimilation.parameters)
    fmt::print("{:<12} {:>22}\n", p.name, fmt::format("{:.4g} ± {:.3g} N/m", p.mean, p.stddev));
  fmt::print(
      "\nTRE of the {} inner fiducials at step {} (the truth's largest mean displacement, {:.1f} "
      "mm) and over the steps:\n",
      r.scenarios.empty() ? 0 : r.scenarios[0].atPeakMm.size(), r.peakStep, r.peakDisplacementMm);
  fmt::print("  {:<34} {:>10} {:>10} {:>20}\n", "scenario", "peak mean", "peak max",
             "over steps mean ± σ");
  static const std::map<std::string, std::string> names = {
      {"vessels", "(i) vessels fixed only"},
      {"prior", "(ii) + atlas springs, prior"},
      {"estimated", "(iii) + springs estimated (ROUKF)"}};
  for (const ScenarioTre& s : r.scenarios)
    fmt::print("  {:<34} {:>7.2f} mm {:>7.2f} mm {:>20}\n", names.at(s.name), s.peakMeanMm,
               s.peakMaxMm,
               fmt::format("{:.2f} ± {:.2f} mm", s.overTime.meanMm, s.overTime.meanStdMm));
  fmt::print("  thesis §5.3 (one cadaver liver, real data): 17.5 -> 16.1 -> 14.0 mm\n");
  fmt::print("assimilation: median {:.1f} ms/step; truth {:.0f} s; {:.0f} s in all\n",
             r.assimilation.medianStepMs, r.truth.wallSeconds, r.seconds);
  fmt::print("results: {}/summary.csv, tre.csv, {}register/transform.csv\n", outDir,
             r.surface ? "camera/detections.csv, " : "track/tracks.csv, ");
}

// The default folder of the livers an atlas is built from: the surface's own folder when it
// holds other annotated livers (a CT liver by name), none for the phantom.
std::string defaultAtlasLivers(const std::string& surface) {
  if (surface == kLiverPhantomName) return "";
  return std::filesystem::path(surface).parent_path().string();
}

class LiverTrackedCommand : public Command {
 public:
  LiverTrackedCommand()
      : Command({"liver", "tracked"},
                "Thesis §5.3 on a CT liver with synthetic tracked tackers: track, register, "
                "and the TRE of three scenarios") {
    args_.options = TrackedLiverOptions::defaultLiver();
    args_.outDir = "out/liver-tracked";
    args_.threadsWhat = "the sigma points' forecasts of the assimilation";
  }

  void declare(CLI::App& app) override {
    args_.declare(app);
    addQuietFlag(app, quiet_);
    addResumeFlag(app, resume_,
                  "its ground-truth, vessels-only and prior runs' checkpoints (the atlas is "
                  "always taken from its folder when complete)");
    TrackedLiverOptions& o = tracked_;
    app.add_option("--tackers", args_.options.markers, "Tackers on the truth's anterior surface")
        ->check(CLI::Range(6, 1000))
        ->capture_default_str();
    app.add_option("--fiducials", args_.options.validationPoints,
                   "Inner fiducials the TRE is measured at (thesis: 9)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    app.add_option("--dropout", o.camera.dropout,
                   "Probability that a tacker goes undetected in a frame")
        ->check(CLI::Range(0.0, 0.99))
        ->capture_default_str();
    app.add_option("--spurious", o.camera.spurious,
                   "Probability, per tacker and frame, of a spurious detection as well")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    checkNonNegative(app.add_option("--camera-offset", o.camera.offset,
                                    "Distance of the camera frame from the model's (m)"))
        ->capture_default_str();
    app.add_option("--camera-angle", o.camera.angleDegrees,
                   "Rotation of the camera frame from the model's (degrees)")
        ->capture_default_str();
    app.add_option("--seed", o.camera.seed, "Seed of the camera's noise, dropouts and pose")
        ->capture_default_str();
    app.add_option("--gate", o.tracker.gate,
                   "Tracking: largest distance (m) from a tacker's predicted position to its "
                   "detection")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--method", method_,
                   "Tracking: optimal (global assignment) or greedy (the thesis' minimal "
                   "distances)")
        ->check(CLI::IsMember({"optimal", "greedy"}))
        ->capture_default_str();
    app.add_option("--observe", observe_,
                   "What the camera gives: tackers (tracked, thesis §5.3) or surface (a partial "
                   "point cloud of the anterior surface, no correspondences)")
        ->check(CLI::IsMember({"tackers", "surface"}))
        ->capture_default_str();
    app.add_option("--surface-coverage", o.surfaceCamera.coverage,
                   "--observe surface: fraction of the liver's surface area the camera sees")
        ->check(CLI::Range(0.01, 1.0))
        ->capture_default_str();
    const int cap = PointCloudSettings{}.maxPoints;  // what the pipeline's thinning keeps
    app.add_option("--surface-points", o.surfaceCamera.pointsPerFrame,
                   fmt::format("--observe surface: points per frame, drawn afresh from the "
                               "visible part (at most its {} samples); over {} a frame is "
                               "averaged on voxel grids to at most {}, as point_cloud.max_points "
                               "does a scene's clouds",
                               o.surfaceCamera.samples, cap, cap))
        ->check(CLI::Range(10, 1000000))
        ->capture_default_str();
    app.add_option("--surface-outliers", o.surfaceCamera.outliers,
                   "--observe surface: fraction of each frame's points that are outliers (in the "
                   "points' box grown by 3 cm)")
        ->check(CLI::Range(0.0, 0.5))
        ->capture_default_str();
    app.add_option("--surface-relinearizations", o.surfaceRelinearizations,
                   "--observe surface: analysis passes after the first per frame, each finding the "
                   "closest points again on the surface the last pass analysed (no forecast "
                   "repeated; stops earlier once a pass moves the estimate by < 0.1 of its spread)")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    app.add_option("--registration-frames", o.registrationFrames,
                   "First frames averaged per tacker and registered onto the model (ICP; "
                   "--observe surface: their points together)")
        ->check(CLI::Range(1, 1000000))
        ->capture_default_str();
    app.add_option("--atlas-livers", atlasLivers_,
                   "Annotated livers the atlas is built from, this one left out (default: the "
                   "surface's folder; 'none': springs on the liver's own curve, as the phantom)");
    app.add_option("--atlas", o.atlasCacheDir,
                   "Folder of the left-out atlas: used when complete, else built there "
                   "(default: OUT/atlas)");
  }

  int run() override {
    TrackedLiverOptions o = tracked_;
    o.liver = args_.resolved();
    o.camera.noise = o.liver.noise;
    o.tracker.assignment =
        method_ == "greedy" ? AssignmentMethod::Greedy : AssignmentMethod::Optimal;
    o.observe = observe_ == "surface" ? TrackedObservation::Surface : TrackedObservation::Tackers;
    o.atlasLiverDir = atlasLivers_.empty()     ? defaultAtlasLivers(o.liver.surface)
                      : atlasLivers_ == "none" ? ""
                                               : atlasLivers_;
    const std::string& outDir = args_.outDir;
    const io::OutputDirectoryLock lock(outDir);
    fmt::print("liver {} -> {} (pipeline-tracked, thesis §5.3)\n", o.liver.surface, outDir);
    std::fflush(stdout);
    const bool surface = o.observe == TrackedObservation::Surface;
    LiverStageDisplay display(
        {{"prepare", "meshing and scenario"},
         {"atlas", "ligament atlas without this liver, transferred onto it"},
         {"truth", surface ? "ground truth (fine Ogden liver, dense ligament) with the surface"
                           : "ground truth (fine Ogden liver, dense ligament) with the tackers"},
         {"camera", surface ? "camera: partial surface clouds, noise, outliers, no correspondences"
                            : "camera: noisy tackers, dropouts, spurious detections, no ids"},
         {"track", "tracking (identities over frames)"},
         {"register", "registration of the first frames onto the model (ICP)"},
         {"estimate", surface
                          ? "assimilation (ROUKF) of the atlas springs from the point clouds"
                          : "assimilation (ROUKF) of the atlas springs from the tracked tackers"},
         {"vessels", "(i) vessels fixed only"},
         {"prior", "(ii) + atlas springs at their prior stiffness"},
         {"estimated", "(iii) + the springs estimated"}},
        quiet_);
    const LiverCallbacks cb = display.callbacks();
    const TrackedLiverReport r = runTrackedLiverPipeline(o, outDir, cb, resume_);
    display.finish();
    printTrackedReport(r, outDir);
    return 0;
  }

 private:
  LiverArguments args_;
  TrackedLiverOptions tracked_;
  std::string method_ = "optimal", observe_ = "tackers", atlasLivers_;
  bool quiet_ = false, resume_ = false;
};

}  // namespace

std::unique_ptr<Command> makeLiverTrackedCommand() {
  return std::make_unique<LiverTrackedCommand>();
}

std::unique_ptr<Command> makeLiverPrepareCommand() {
  return std::make_unique<LiverPrepareCommand>();
}
std::unique_ptr<Command> makeLiverRunCommand() { return std::make_unique<LiverRunCommand>(); }

}  // namespace bcassim
