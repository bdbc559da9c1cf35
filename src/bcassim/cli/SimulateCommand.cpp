// `bcassim simulate SCENE`: runs a YAML scene (and its variants) forward in time and prints one
// line per run, plus a table comparing the variants.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "bcassim/cli/Commands.h"
#include "bcassim/cli/ProgressBar.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/io/OutputDirectoryLock.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"

namespace bcassim {
namespace {

void printScene(const std::string& scenePath, const Scene& scene) {
  const TetMesh& mesh = *scene.model.mesh;
  fmt::print("scene {}: {} nodes, {} tets, {} markers, {} springs, {} steps of {:.6g} s{}\n",
             scenePath, mesh.numNodes(), mesh.numTets(), scene.markers.points.size(),
             scene.model.springs.springs().size(), scene.steps, scene.dt(),
             scene.variants.empty() ? ""
                                    : fmt::format(", {} variant{}", scene.variants.size(),
                                                  scene.variants.size() == 1 ? "" : "s"));
  std::fflush(stdout);
}

void printRuns(const SimulationResult& result, const std::string& outDir) {
  for (const RunResult& r : result.runs)
    fmt::print(
        "{}: {} steps, {:.3g} ms/step, {:.3g} s in all, {} frames, max displacement "
        "{:.4g} mm (markers {:.4g} mm) -> {}\n",
        r.name, r.steps, r.meanStepMs, r.wallSeconds, r.frames, 1e3 * r.maxNodeDisplacement,
        1e3 * r.maxMarkerDisplacement, r.outDir);
  if (result.runs.size() < 2) return;
  fmt::print("\n{:<20} {:>16} {:>16} {:>12}\n", "variant", "rel.diff final", "rel.diff all",
             "ms/step");
  for (const RunResult& r : result.runs)
    fmt::print("{:<20} {:>15.3f}% {:>15.3f}% {:>12.3g}\n", r.name, 100 * r.relativeDifferenceFinal,
               100 * r.relativeDifferenceAll, r.meanStepMs);
  fmt::print("(relative to the largest marker displacement of '{}'; table in {})\n",
             result.runs.front().name, (std::filesystem::path(outDir) / "variants.csv").string());
}

class SimulateCommand : public Command {
 public:
  SimulateCommand() : Command({"simulate"}, "Run a YAML scene forward in time") {}

  void declare(CLI::App& app) override {
    app.add_option("scene", scenePath_, "Scene file (.yaml), see docs/scene-format.md")->required();
    addOutOption(app, outDir_);
    addQuietFlag(app, quiet_);
    addResumeFlag(app, resume_,
                  "its last checkpoint (written at every output step); with a direct solver "
                  "the same files byte for byte as a run that never stopped");
  }

  int run() override {
    const io::OutputDirectoryLock lock(outDir_);
    const Scene scene = loadScene(scenePath_);
    printScene(scenePath_, scene);
    ProgressBar bar(stderr);
    ProgressCallback progress;
    if (!quiet_) progress = [&bar](const RunProgress& p) { bar.update(p); };
    const SimulationResult result = runSimulation(scene, outDir_, progress, resume_);
    bar.finish();
    printRuns(result, outDir_);
    return 0;
  }

 private:
  std::string scenePath_, outDir_ = "out";
  bool quiet_ = false, resume_ = false;
};

}  // namespace

std::unique_ptr<Command> makeSimulateCommand() { return std::make_unique<SimulateCommand>(); }

}  // namespace bcassim
