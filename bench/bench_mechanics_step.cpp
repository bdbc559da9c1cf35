// Per-step cost of the forward model: force + tangent assembly, CHOLMOD numeric factorisation of
// the implicit-Euler matrix (eq. 2.16), a direct solve with a stored factor, and full implicit-
// Euler steps with "cholmod" (factorise every step) and "factorized-pcg" (thesis §4.5: factor
// stored once, PCG reuses it). Scenes: the thesis cylinder (930 nodes) and a ~2,200-node
// cylinder, plain and with mean dilatation (_md4); plus assembly alone on the 15x3x3 cm beam with
// ~8,600 tets for every material.
//
// Targets (SPEC / brief): StVK assembly of ~8,600 tets <= 5 ms on one core; reuse-PCG step at
// ~2,200 nodes <= 10 ms. Run through scripts/bench.sh, which sets one thread.
#include <algorithm>
#include <string>
#include <utility>

#include "BenchScenes.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"

namespace bcassim::bench {
namespace {

constexpr int kWarmupSteps = 25;  // the sine load peaks at t = 0.25 s
constexpr int kTimedSteps = 100;  // one full load period (1 s) per repetition

void BM_Assembly(benchmark::State& st, int targetNodes, int patchTets = 1) {
  const Scene scene = makeCylinderScene(targetNodes, "stvk", patchTets);
  const MechanicalState s = warmedUpState(scene, kWarmupSteps);
  Eigen::VectorXd f;
  SparseMatrix K = scene.model.pattern->emptyMatrix();
  for (auto _ : st) {
    scene.model.internalForcesAndStiffness(s.t, s.x, f, K);
    benchmark::DoNotOptimize(K.valuePtr());
    benchmark::ClobberMemory();
  }
  addMeshCounters(st, scene.model);
}

void BM_CholmodFactorize(benchmark::State& st, int targetNodes, int patchTets = 1) {
  const Scene scene = makeCylinderScene(targetNodes, "stvk", patchTets);
  const MechanicalState s = warmedUpState(scene, kWarmupSteps);
  SparseMatrix A = scene.model.pattern->emptyMatrix();
  Eigen::VectorXd rhs;
  implicitEulerSystem(scene, s, A, rhs);
  CholeskyFactor factor;
  factor.analyzePattern(A);
  for (auto _ : st) {
    factor.factorize(A);
    benchmark::ClobberMemory();
  }
  addMeshCounters(st, scene.model);
  st.counters["dofs"] = static_cast<double>(A.rows());
  st.counters["nnz_A"] = static_cast<double>(A.nonZeros());
  st.counters["nnz_L"] = static_cast<double>(factor.factorNonZeros());
}

// precision: "double" = CHOLMOD's solve, "double-sweep" = our supernodal sweep in double,
// "single" = the same sweep on L rounded to float (the single-precision preconditioner).
void BM_CholmodSolve(benchmark::State& st, int targetNodes, const std::string& precision) {
  const Scene scene = makeCylinderScene(targetNodes);
  const MechanicalState s = warmedUpState(scene, kWarmupSteps);
  SparseMatrix A = scene.model.pattern->emptyMatrix();
  Eigen::VectorXd rhs, x;
  implicitEulerSystem(scene, s, A, rhs);
  CholeskyFactor factor;
  factor.factorize(A);
  CholeskyFactor::Workspace work;
  for (auto _ : st) {
    if (precision == "single")
      factor.solveSinglePrecision(rhs, x, work);
    else if (precision == "double-sweep")
      factor.solveSupernodalDouble(rhs, x, work);
    else
      factor.solve(rhs, x, work);
    benchmark::DoNotOptimize(x.data());
  }
  addMeshCounters(st, scene.model);
  st.counters["rel_residual"] = (A * x - rhs).norm() / rhs.norm();
}

// Full implicit-Euler steps, continuing the simulation over kTimedSteps steps (one load period).
// policy configures factorized-pcg (default RefreshPolicy: never refresh on schedule, refresh when
// PCG needs more than 20 iterations, relTol 1e-10).
void BM_Step(benchmark::State& st, int targetNodes, const char* solverName,
             RefreshPolicy policy = {}, const std::string& material = "stvk", int patchTets = 1) {
  const Scene scene = makeCylinderScene(targetNodes, material, patchTets);
  MechanicalState s = warmedUpState(scene, kWarmupSteps);
  ImplicitEuler euler(scene.model, makeLinearSolver(solverName, policy), {scene.dt});
  euler.step(scene.model, s);  // untimed: factorised here (factorized-pcg keeps this factor)
  auto* pcg = dynamic_cast<FactorizedPcgSolver*>(&euler.linearSolver());
  const int factorizationsBefore = pcg ? pcg->factorizations() : 0;
  double assembly = 0, solve = 0, iterations = 0, maxIterations = 0, refreshed = 0;
  for (auto _ : st) {
    euler.step(scene.model, s);
    const StepTimings& t = euler.lastTimings();
    assembly += t.assembly;
    solve += t.solve;
    iterations += t.lastSolve.iterations;
    maxIterations = std::max<double>(maxIterations, t.lastSolve.iterations);
    refreshed += t.lastSolve.refactorized ? 1 : 0;
  }
  addMeshCounters(st, scene.model);
  using C = benchmark::Counter;
  st.counters["assembly_ms"] = C(1e3 * assembly, C::kAvgIterations);
  st.counters["solve_ms"] = C(1e3 * solve, C::kAvgIterations);
  if (pcg) {
    st.counters["pcg_iters"] = C(iterations, C::kAvgIterations);
    st.counters["pcg_iters_max"] = maxIterations;
    st.counters["refactorizations"] = pcg->factorizations() - factorizationsBefore;
    st.counters["refreshed_solves"] = refreshed;
  }
  const Eigen::VectorXd u = s.x - scene.model.restPositions();
  st.counters["max_u_mm"] = 1e3 * u.reshaped(3, u.size() / 3).colwise().norm().maxCoeff();
}

// Assembly alone on the 15x3x3 cm beam (~8,600 tets), bent, for each material.
void BM_BeamAssembly(benchmark::State& st, const std::string& material) {
  const Scene scene = makeBeamScene(8600, material);
  const Eigen::VectorXd x = bentBeamPositions(scene.model);
  Eigen::VectorXd f;
  SparseMatrix K = scene.model.pattern->emptyMatrix();
  for (auto _ : st) {
    scene.model.internalForcesAndStiffness(0.0, x, f, K);
    benchmark::DoNotOptimize(K.valuePtr());
    benchmark::ClobberMemory();
  }
  addMeshCounters(st, scene.model);
  st.counters["inverted"] = static_cast<double>(scene.model.elasticity.lastInvertedCount());
}

void registerAll() {
  using benchmark::kMillisecond;
  using benchmark::State;
  for (int n : {915, 2200}) {
    const std::string p = "cylinder" + std::to_string(n) + "/";
    benchmark::RegisterBenchmark((p + "assembly").c_str(), [n](State& st) {
      BM_Assembly(st, n);
    })->Unit(kMillisecond);
    benchmark::RegisterBenchmark((p + "cholmod_factorize").c_str(), [n](State& st) {
      BM_CholmodFactorize(st, n);
    })->Unit(kMillisecond);
    for (std::string precision : {"double", "double-sweep", "single"})
      benchmark::RegisterBenchmark(
          (p + "cholmod_solve" + (precision == "double" ? "" : "_" + precision)).c_str(),
          [n, precision](State& st) { BM_CholmodSolve(st, n, precision); })
          ->Unit(kMillisecond);
    benchmark::RegisterBenchmark((p + "step_cholmod").c_str(),
                                 [n](State& st) { BM_Step(st, n, "cholmod"); })
        ->Unit(kMillisecond)
        ->Iterations(kTimedSteps)
        ->UseRealTime();
    benchmark::RegisterBenchmark((p + "step_factorized_pcg").c_str(),
                                 [n](State& st) { BM_Step(st, n, "factorized-pcg"); })
        ->Unit(kMillisecond)
        ->Iterations(kTimedSteps)
        ->UseRealTime();
    // Same with a looser PCG tolerance (the default 1e-10 is far below any observation noise).
    for (const auto& [tol, label] : {std::pair{1e-8, "1e-8"}, std::pair{1e-6, "1e-6"}}) {
      RefreshPolicy policy;
      policy.relTol = tol;
      benchmark::RegisterBenchmark(
          (p + "step_factorized_pcg_tol" + label).c_str(),
          [n, policy](State& st) { BM_Step(st, n, "factorized-pcg", policy); })
          ->Unit(kMillisecond)
          ->Iterations(kTimedSteps)
          ->UseRealTime();
    }
    // The default policy (single-precision preconditioning) with the factor used in double.
    {
      RefreshPolicy policy;
      policy.singlePrecision = false;
      benchmark::RegisterBenchmark(
          (p + "step_factorized_pcg_double").c_str(),
          [n, policy](State& st) { BM_Step(st, n, "factorized-pcg", policy); })
          ->Unit(kMillisecond)
          ->Iterations(kTimedSteps)
          ->UseRealTime();
    }
    // Refresh every 2 or 4 steps on the second core while the old factor keeps preconditioning
    // (default relTol 1e-10), with the factor in single (default) and in double precision.
    for (bool single : {false, true})
      for (int every : {2, 4}) {
        RefreshPolicy policy;
        policy.everyNMatrices = every;
        policy.background = true;
        policy.singlePrecision = single;
        benchmark::RegisterBenchmark(
            (p + "step_factorized_pcg_background_every" + std::to_string(every) +
             (single ? "" : "_double"))
                .c_str(),
            [n, policy](State& st) { BM_Step(st, n, "factorized-pcg", policy); })
            ->Unit(kMillisecond)
            ->Iterations(kTimedSteps)
            ->UseRealTime();
      }
    // Mean dilatation over 4-tet patches: denser matrix (each patch couples its ~7 nodes).
    benchmark::RegisterBenchmark((p + "assembly_md4").c_str(), [n](State& st) {
      BM_Assembly(st, n, 4);
    })->Unit(kMillisecond);
    benchmark::RegisterBenchmark((p + "cholmod_factorize_md4").c_str(), [n](State& st) {
      BM_CholmodFactorize(st, n, 4);
    })->Unit(kMillisecond);
    benchmark::RegisterBenchmark(
        (p + "step_factorized_pcg_md4").c_str(),
        [n](State& st) { BM_Step(st, n, "factorized-pcg", {}, "stvk", 4); })
        ->Unit(kMillisecond)
        ->Iterations(kTimedSteps)
        ->UseRealTime();
    // Sanity check of the reuse: with the linear material the system matrix never changes, so
    // the stored factor is exact and PCG should need one or two iterations per step.
    benchmark::RegisterBenchmark((p + "step_factorized_pcg_linear").c_str(),
                                 [n](State& st) { BM_Step(st, n, "factorized-pcg", {}, "linear"); })
        ->Unit(kMillisecond)
        ->Iterations(kTimedSteps)
        ->UseRealTime();
  }
  for (std::string m : {"linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"})
    benchmark::RegisterBenchmark(("beam8600/assembly/" + m).c_str(), [m](State& st) {
      BM_BeamAssembly(st, m);
    })->Unit(kMillisecond);
}

}  // namespace
}  // namespace bcassim::bench

int main(int argc, char** argv) {
  bcassim::bench::registerAll();
  return bcassim::bench::runBenchmarks(argc, argv);
}
