// Thesis Table 2.1 analogue: the 15 x 3 x 3 cm beam with ~26,000 tets, fixed at x = 0, bending
// load on the bottom face, E 1.542 MPa nu 0.49, one implicit-Euler step per iteration for each
// material. The thesis reports ms per iteration (mean over 500): corotational 402.73, StVK
// 425.02, Neo-Hookean 451.64, Mooney-Rivlin 503.68 (ratios 1 : 1.055 : 1.121 : 1.251).
// scripts/bench.sh prints the ratios to corotational next to those figures.
//
// Benchmarks, per material:
//   beam26000/step_cholmod/<m>         full step, CHOLMOD factorisation every step
//   beam26000/step_factorized_pcg/<m>  full step, factor of the first step reused by PCG
//   beam26000/assembly/<m>             force + tangent assembly alone, on a bent configuration
#include <algorithm>
#include <string>

#include "BenchScenes.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"

namespace bcassim::bench {
namespace {

constexpr int kTargetTets = 26000;
constexpr int kCholmodSteps = 10;  // timed steps per repetition after one untimed first step
constexpr int kPcgSteps = 20;      // more for PCG: its cost varies with the refreshes

void BM_Step(benchmark::State& st, const std::string& material, const char* solverName) {
  const Scene scene = makeBeamScene(kTargetTets, material);
  MechanicalState s = scene.model.restState();
  ImplicitEuler euler(scene.model, makeLinearSolver(solverName), {scene.dt});
  euler.step(scene.model, s);  // untimed: first factorisation
  auto* pcg = dynamic_cast<FactorizedPcgSolver*>(&euler.linearSolver());
  const int factorizationsBefore = pcg ? pcg->factorizations() : 0;
  double assembly = 0, solve = 0, iterations = 0;
  for (auto _ : st) {
    euler.step(scene.model, s);
    assembly += euler.lastTimings().assembly;
    solve += euler.lastTimings().solve;
    iterations += euler.lastTimings().lastSolve.iterations;
  }
  addMeshCounters(st, scene.model);
  using C = benchmark::Counter;
  st.counters["assembly_ms"] = C(1e3 * assembly, C::kAvgIterations);
  st.counters["solve_ms"] = C(1e3 * solve, C::kAvgIterations);
  if (pcg) {
    st.counters["pcg_iters"] = C(iterations, C::kAvgIterations);
    st.counters["refactorizations"] = pcg->factorizations() - factorizationsBefore;
  }
  // Vertical displacement of the most deflected node, mm: the materials should agree closely.
  Eigen::VectorXd u = s.x - scene.model.restPositions();
  double maxDz = 0;
  for (Eigen::Index i = 0; i < scene.model.mesh->numNodes(); ++i)
    maxDz = std::max(maxDz, std::abs(u(3 * i + 2)));
  st.counters["max_uz_mm"] = 1e3 * maxDz;
}

void BM_Assembly(benchmark::State& st, const std::string& material) {
  const Scene scene = makeBeamScene(kTargetTets, material);
  const Eigen::VectorXd x = bentBeamPositions(scene.model);
  Eigen::VectorXd f;
  SparseMatrix K = scene.model.pattern->emptyMatrix();
  for (auto _ : st) {
    scene.model.internalForcesAndStiffness(0.0, x, f, K);
    benchmark::DoNotOptimize(K.valuePtr());
    benchmark::ClobberMemory();
  }
  addMeshCounters(st, scene.model);
}

void registerAll() {
  using benchmark::kMillisecond;
  using benchmark::State;
  const std::string p = "beam" + std::to_string(kTargetTets) + "/";
  for (std::string m : {"corotational", "stvk", "neohookean", "mooneyrivlin", "linear"}) {
    benchmark::RegisterBenchmark((p + "step_cholmod/" + m).c_str(),
                                 [m](State& st) { BM_Step(st, m, "cholmod"); })
        ->Unit(kMillisecond)
        ->Iterations(kCholmodSteps)
        ->UseRealTime();
    benchmark::RegisterBenchmark((p + "step_factorized_pcg/" + m).c_str(),
                                 [m](State& st) { BM_Step(st, m, "factorized-pcg"); })
        ->Unit(kMillisecond)
        ->Iterations(kPcgSteps)
        ->UseRealTime();
    benchmark::RegisterBenchmark((p + "assembly/" + m).c_str(), [m](State& st) {
      BM_Assembly(st, m);
    })->Unit(kMillisecond);
  }
}

}  // namespace
}  // namespace bcassim::bench

int main(int argc, char** argv) {
  bcassim::bench::registerAll();
  return bcassim::bench::runBenchmarks(argc, argv);
}
