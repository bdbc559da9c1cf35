// The liver assimilation step (issue 4: <= 33 ms on 2 cores): one ROUKF step of the ~2,150-node
// estimation liver, 11 sigma points, for each way of stepping the sigma points:
//   own        each sigma point its own eq. 2.16 step, PCG preconditioned by worker 0's shared
//              factorisation (thesis Alg. 4/5)
//   mean       every sigma point steps with the tangent of the analysed mean, factorised once per
//              step at the end of the previous one (FrozenTangent)
//   mean-bg    the same tangent built on a thread of its own while the next steps run
// on 1 and 2 threads. Validation and tumour logging are switched off: only the filter step runs.
// A small driver rather than Google Benchmark: each configuration is a whole run, and the table
// gives the median over its steps (after 5 warm-up steps) with the per-step CPU breakdown.
//
// First it builds the mean's tangent at rest 11 times on one thread and prints the medians of
// its parts (FrozenTangent: assembly, factorisation, the springs' correction).
//
//   bench_liver_step [SURFACE|NAME|phantom] [STEPS] [OUT_DIR] [MODES]
//   (defaults: phantom 100 out/bench own,mean,mean-bg)
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bcassim/experiments/liver/LiverPhantom.h"
#include "bcassim/experiments/liver/LiverScenario.h"
#include "bcassim/experiments/liver/LiverSurfacePath.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Row {
  std::string mode;
  int threads = 1;
  double step = 0, forecast = 0, correction = 0, assembly = 0, solve = 0, tangent = 0, its = 0;
  double mean = 0, p95 = 0, max = 0;  // of the step
};

Row measure(const std::filesystem::path& dir, const std::string& mode, int threads, int steps) {
  bcassim::Scene scene = bcassim::loadScene((dir / "estimate.yaml").string());
  scene.steps = steps;
  bcassim::AssimilationSettings& s = *scene.assimilation;
  s.threads = threads;
  s.meanTangent = mode != "own";
  s.tangentInBackground = mode == "mean-bg";
  s.reuseFactorization = true;
  s.validationTruth.reset();
  scene.hidden.points.clear();
  const std::filesystem::path out = dir / "bench" / fmt::format("{}-{}", mode, threads);
  bcassim::runAssimilation(scene, out.string());
  const bcassim::CsvTable t = bcassim::readCsvTable((out / "timing.csv").string());
  auto values = [&](const std::string& name) {
    const int c = t.column(name);
    std::vector<double> v;
    for (Eigen::Index r = 5; r < t.rows.rows(); ++r) v.push_back(t.rows(r, c));
    return v;
  };
  auto column = [&](const std::string& name) { return median(values(name)); };
  // Tangents are built every few steps: their cost per step is the mean, not the median.
  auto perStep = [&](const std::string& name) {
    const std::vector<double> v = values(name);
    double sum = 0;
    for (double x : v) sum += x;
    return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
  };
  std::vector<double> totals = values("total_ms");
  std::sort(totals.begin(), totals.end());
  const double p95 =
      totals.empty() ? 0.0
                     : totals[static_cast<size_t>(0.95 * static_cast<double>(totals.size() - 1))];
  return {mode,
          threads,
          column("total_ms"),
          column("forecast_ms"),
          column("correction_ms"),
          column("assembly_cpu_ms"),
          column("solve_cpu_ms"),
          perStep("tangent_cpu_ms"),
          column("linear_iterations"),
          perStep("total_ms"),
          p95,
          totals.empty() ? 0.0 : totals.back()};
}

// Medians of FrozenTangent::build's parts at the rest state of the estimation scene (ms).
void printTangentBuild(const std::filesystem::path& dir) {
  const bcassim::Scene scene = bcassim::loadScene((dir / "estimate.yaml").string());
  const bcassim::MechanicalState rest = scene.model.restState();
  std::vector<double> assembly, factorization, springs, total;
  std::shared_ptr<const bcassim::FrozenTangent> previous;
  for (int i = 0; i < 11; ++i) {
    auto t = bcassim::FrozenTangent::build(scene.model, rest, scene.dt(),
                                           previous ? &previous->factor() : nullptr);
    assembly.push_back(1e3 * t->assemblySeconds());
    factorization.push_back(1e3 * t->factorizationSeconds());
    springs.push_back(1e3 * t->springSeconds());
    total.push_back(1e3 * t->buildSeconds());
    previous = t;
  }
  std::cout << fmt::format(
      "tangent build at rest, one thread, median of 11 (ms): total {:.1f} = assembly {:.1f} + "
      "factorisation {:.1f} + springs' correction {:.1f} ({} springs)\n\n",
      median(total), median(assembly), median(factorization), median(springs),
      scene.model.springs.springs().size());
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string liver = argc > 1 ? argv[1] : bcassim::kLiverPhantomName;
    const int steps = argc > 2 ? std::stoi(argv[2]) : 100;
    const std::filesystem::path out = argc > 3 ? argv[3] : "out/bench";
    const std::string modes = argc > 4 ? argv[4] : "own,mean,mean-bg";
    bcassim::LiverScenarioOptions o;
    o.surface = bcassim::resolveLiverSurface(liver);
    o.fineNodes = 3000;  // the truth only supplies the observed tracks here
    o.steps = o.observedSteps = steps;
    const std::filesystem::path dir =
        out / ("liver-" + std::filesystem::path(liver).stem().string());
    const bcassim::LiverScenario scenario = bcassim::prepareLiverScenario(o, dir.string());
    bcassim::runSimulation(bcassim::loadScene((dir / "truth.yaml").string()),
                           (dir / "truth").string());

    printTangentBuild(dir);
    std::vector<Row> rows;
    for (const char* mode : {"own", "mean", "mean-bg"})
      for (int threads : {1, 2}) {
        if (("," + modes + ",").find(std::string(",") + mode + ",") == std::string::npos) continue;
        rows.push_back(measure(dir, mode, threads, steps));
        std::fprintf(stderr, "%s, %d thread(s): %.1f ms\n", mode, threads, rows.back().step);
      }
    if (rows.empty())
      throw std::invalid_argument("no mode among '" + modes + "' (own, mean, mean-bg)");
    std::cout << fmt::format(
        "liver {} ({} estimation nodes), {} steps of 0.02 s, 11 sigma points; medians (and mean, "
        "p95, max of the step) over steps "
        "6..{}\n\n",
        liver, scenario.coarse.outputNodes, steps, steps);
    std::cout << "| tangent | threads | step (ms) | mean | p95 | max | forecast | correction | "
                 "assembly CPU | solve CPU "
                 "| tangent CPU (mean per step) | PCG its / sigma point | vs own, 1 thread |\n"
                 "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Row& r : rows)
      std::cout << fmt::format(
          "| {} | {} | **{:.1f}** | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.2f} | {:.1f} | {:.1f} | "
          "{:.1f} | {:.1f} | {:.1f}x |\n",
          r.mode, r.threads, r.step, r.mean, r.p95, r.max, r.forecast, r.correction, r.assembly,
          r.solve, r.tangent, r.its, rows[0].step / r.step);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bench_liver_step: error: " << e.what() << "\n";
    return 2;
  }
}
