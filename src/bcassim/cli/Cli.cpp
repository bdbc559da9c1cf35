#include "bcassim/cli/Cli.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <new>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/VectorFormat.h"
#include "bcassim/cli/AssimilationProgressBar.h"
#include "bcassim/cli/AtlasCommands.h"
#include "bcassim/cli/LiverCommand.h"
#include "bcassim/cli/ProgressBar.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/mesh/MeshQuality.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "bcassim/viz/PlotScripts.h"

#ifndef BCASSIM_VERSION
#define BCASSIM_VERSION "0.1.0"
#endif

namespace bcassim {

namespace {

// Exit codes: 0 success, 1 internal error, 2 bad input (file, scene, arguments), 3 numerical
// failure during a run.
constexpr int kExitInternal = 1;
constexpr int kExitInput = 2;
constexpr int kExitNumerical = 3;

// The error on one line, whatever the exception text holds.
void printError(const std::string& what) {
  std::string line = what;
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  fmt::print(stderr, "bcassim: error: {}\n", line);
}

int simulate(const std::string& scenePath, const std::string& outDir, bool quiet, bool resume) {
  const Scene scene = loadScene(scenePath);
  const TetMesh& mesh = *scene.model.mesh;
  fmt::print("scene {}: {} nodes, {} tets, {} markers, {} springs, {} steps of {:.6g} s{}\n",
             scenePath, mesh.numNodes(), mesh.numTets(), scene.markers.points.size(),
             scene.model.springs.springs().size(), scene.steps, scene.dt(),
             scene.variants.empty() ? ""
                                    : fmt::format(", {} variant{}", scene.variants.size(),
                                                  scene.variants.size() == 1 ? "" : "s"));
  std::fflush(stdout);
  ProgressBar bar(stderr);
  ProgressCallback progress;
  if (!quiet) progress = [&bar](const RunProgress& p) { bar.update(p); };
  const SimulationResult result = runSimulation(scene, outDir, progress, resume);
  bar.finish();

  for (const RunResult& r : result.runs)
    fmt::print(
        "{}: {} steps, {:.3g} ms/step, {:.3g} s in all, {} frames, max displacement "
        "{:.4g} mm (markers {:.4g} mm) -> {}\n",
        r.name, r.steps, r.meanStepMs, r.wallSeconds, r.frames, 1e3 * r.maxNodeDisplacement,
        1e3 * r.maxMarkerDisplacement, r.outDir);
  if (result.runs.size() > 1) {
    fmt::print("\n{:<20} {:>16} {:>16} {:>12}\n", "variant", "rel.diff final", "rel.diff all",
               "ms/step");
    for (const RunResult& r : result.runs)
      fmt::print("{:<20} {:>15.3f}% {:>15.3f}% {:>12.3g}\n", r.name,
                 100 * r.relativeDifferenceFinal, 100 * r.relativeDifferenceAll, r.meanStepMs);
    fmt::print("(relative to the largest marker displacement of '{}'; table in {})\n",
               result.runs.front().name, (std::filesystem::path(outDir) / "variants.csv").string());
  }
  return 0;
}

// PNG plots of an output directory when python3 with matplotlib is there; one line either way.
void plot(const std::string& outDir) {
  const std::string problem = runPlotScript("plot_assimilation.py", {outDir});
  if (!problem.empty()) fmt::print("plots skipped: {}\n", problem);
}

const char* filterName(FilterKind k) {
  return k == FilterKind::Ukf ? "ukf" : k == FilterKind::Roukf ? "roukf" : "etkf";
}

void printSceneLine(const std::string& scenePath, const Scene& scene) {
  const AssimilationSettings& s = *scene.assimilation;
  fmt::print(
      "scene {}: {} nodes, {} markers, {} validation points, {} parameter{}, filter {}, "
      "{} thread{}, {} steps of {:.6g} s, observations until step {}\n",
      scenePath, scene.model.mesh->numNodes(), scene.markers.points.size(),
      scene.validation.points.size(), s.parameters.size(), s.parameters.size() == 1 ? "" : "s",
      filterName(s.filter), s.threads, s.threads == 1 ? "" : "s", scene.steps, scene.dt(),
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

int assimilate(const std::string& scenePath, const std::string& estimatesPath,
               const std::string& outDir, bool quiet, bool plots, bool resume) {
  const Scene scene = loadScene(scenePath);
  if (!scene.assimilation)
    throw InputError(scenePath + ": no assimilation: section (see docs/assimilation-format.md)");
  const bool validating = !estimatesPath.empty();
  if (validating && !scene.assimilation->validationTruth)
    throw InputError(scenePath +
                     ": assimilation.validation.tracks: missing (truth of the validation points)");
  printSceneLine(scenePath, scene);
  AssimilationProgressBar bar(stderr);
  AssimilationCallback progress;
  if (!quiet) progress = [&bar](const AssimilationProgress& p) { bar.update(p); };
  const AssimilationResult result = validating
                                        ? runValidation(scene, estimatesPath, outDir, progress)
                                        : runAssimilation(scene, outDir, progress, resume);
  bar.finish();
  printSummary(result, !validating);
  if (plots) plot(outDir);
  return 0;
}

int meshInfo(const std::string& path, const std::string& regionField) {
  const TetMesh mesh = readTetMesh(path, regionField);
  const MeshQuality q = measureQuality(mesh);
  std::map<int, long> tetsPerRegion;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) ++tetsPerRegion[mesh.regionOf(t)];
  std::string regions;
  for (const auto& [id, count] : tetsPerRegion)
    regions += fmt::format("{}{} ({} tets)", regions.empty() ? "" : ", ", id, count);
  fmt::print("file: {}\n", path);
  fmt::print("nodes: {}\n", q.numNodes);
  fmt::print("tets: {}\n", q.numTets);
  fmt::print("regions: {}\n", regions.empty() ? "none" : regions);
  fmt::print("bounding box: {} .. {} m (size {} m)\n", formatVec3(q.bboxMin), formatVec3(q.bboxMax),
             formatVec3(q.bboxMax - q.bboxMin));
  fmt::print("volume: {:.6g} m^3\n", q.totalVolume);
  fmt::print("tet volume: min {:.6g} m^3, max {:.6g} m^3\n", q.minVolume, q.maxVolume);
  fmt::print("inverted tets: {}\n", q.numInverted);
  fmt::print("dihedral angle: min {:.3f} deg, max {:.3f} deg\n", q.minDihedralDeg,
             q.maxDihedralDeg);
  return 0;
}

int run(int argc, char** argv) {
  CLI::App app{"bcassim: boundary conditions of organ models by Kalman filtering", "bcassim"};
  app.set_version_flag("--version", std::string("bcassim ") + BCASSIM_VERSION);
  app.require_subcommand(1);

  std::string scenePath, outDir = "out";
  bool quiet = false;
  CLI::App* sim = app.add_subcommand("simulate", "Run a YAML scene forward in time");
  sim->add_option("scene", scenePath, "Scene file (.yaml), see docs/scene-format.md")->required();
  sim->add_option("-o,--out", outDir, "Output directory (created if missing)")
      ->capture_default_str();
  sim->add_flag("-q,--quiet", quiet, "No progress bar");
  bool resume = false;
  sim->add_flag("--resume", resume,
                "Continue a stopped run in --out from its last checkpoint (written at every "
                "output step)");

  bool noPlots = false;
  std::string estimatesPath;
  CLI::App* assim =
      app.add_subcommand("assimilate", "Estimate a scene's parameters from observed tracks");
  assim->add_option("scene", scenePath, "Scene file with an assimilation: section")->required();
  assim->add_option("-o,--out", outDir, "Output directory (created if missing)")
      ->capture_default_str();
  assim->add_flag("-q,--quiet", quiet, "No progress bar");
  assim->add_flag("--no-plots", noPlots, "Do not draw the PNG plots");
  bool resumeAssimilation = false;
  assim->add_flag("--resume", resumeAssimilation,
                  "Continue a stopped run in --out from its last checkpoint (written every "
                  "output.every steps)");
  CLI::App* val = app.add_subcommand(
      "validate", "Forward run with estimated parameters against the truth validation tracks");
  val->add_option("scene", scenePath, "Scene file with an assimilation: section")->required();
  val->add_option("--estimates", estimatesPath, "estimates.csv of an assimilate run (last step)")
      ->required();
  val->add_option("-o,--out", outDir, "Output directory (created if missing)")
      ->capture_default_str();
  val->add_flag("-q,--quiet", quiet, "No progress bar");
  val->add_flag("--no-plots", noPlots, "Do not draw the PNG plots");

  CLI::App* mesh = app.add_subcommand("mesh", "Mesh tools");
  mesh->require_subcommand(1);
  std::string meshPath, regionField;
  CLI::App* info = mesh->add_subcommand("info", "Counts, regions, bounding box and quality");
  info->add_option("file", meshPath, "Tet mesh (.vtk, .vtu, .msh), coordinates in metres")
      ->required();
  info->add_option("--region-field", regionField, "Integer cell array holding the region ids");
  addAtlasCommands(app);

  const LiverCommand liver(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    printError(std::string(e.what()) + " (see 'bcassim --help')");
    return kExitInput;
  }
  if (sim->parsed()) return simulate(scenePath, outDir, quiet, resume);
  if (info->parsed()) return meshInfo(meshPath, regionField);
  if (assim->parsed())
    return assimilate(scenePath, "", outDir, quiet, !noPlots, resumeAssimilation);
  if (val->parsed()) return assimilate(scenePath, estimatesPath, outDir, quiet, !noPlots, false);
  if (liver.parsed()) return liver.run();
  return kExitInput;
}

}  // namespace

int runCli(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const InputError& e) {
    printError(e.what());
    return kExitInput;
  } catch (const NumericalError& e) {
    printError(e.what());
    return kExitNumerical;
  } catch (const std::filesystem::filesystem_error& e) {
    printError(e.what());
    return kExitInput;
  } catch (const std::bad_alloc&) {
    printError("out of memory");
    return kExitInternal;
  } catch (const std::exception& e) {
    printError(std::string("internal error: ") + e.what());
    return kExitInternal;
  } catch (...) {
    printError("internal error: unknown exception");
    return kExitInternal;
  }
}

}  // namespace bcassim
