// The parts of a static registration frame (issue 14: <= 50 ms per frame on 2 cores) on the
// mestdagh-liver estimation mesh (mesh-remeshed: 3,829 nodes, Neo-Hookean E 4.5 kPa, nu 0.49, its
// Dirichlet vertices fixed) deformed by a 1 N tool force on its force zone: force assembly, force
// + stiffness assembly, CHOLMOD's numeric factorisation of K, a solve with the factor (double and
// single precision), and one chord step (StaticSolver::chordSolve: force assembly, solve). Without
// $BCASSIM_DATA/mestdagh-liver, a ~3,800-node cylinder of the same law stands in (labelled so).
#include <cstdlib>
#include <filesystem>
#include <string>

#include "BenchScenes.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"
#include "bcassim/scene/SceneLoader.h"

namespace bcassim::bench {
namespace {

namespace fs = std::filesystem;

struct StaticFrame {
  bcassim::Scene scene;
  Eigen::VectorXd x;  // the equilibrium under the tool force at t = 1 s
  std::string label;
};

// The estimation mesh and law of the mestdagh-liver registration, or the stand-in; `label` says
// which.
bcassim::Scene frameScene(std::string& label) {
  const char* env = std::getenv("BCASSIM_DATA");
  const fs::path data = fs::path(env ? env : "../shared/data") / "mestdagh-liver";
  const std::string law =
      "material: {model: neohookean, young_modulus: 4500, poisson_ratio: 0.49}\n"
      "integrator: {type: static, tolerance: 1.0e-8}\n"
      "time: {dt: 1, steps: 1}\n"
      "solver: {type: cholmod}\n";
  if (fs::exists(data / "mesh-remeshed" / "liver.msh")) {
    label = "mestdagh-remeshed";
    return loadSceneFromString(
        "mesh: {file: \"" + (data / "mesh-remeshed/liver.msh").string() + "\"}\n" + law +
            "fixed:\n  - region: {nodes_file: \"" +
            (data / "mesh-remeshed/dirichlet-vertices.npy").string() +
            "\"}\nloads:\n  - region: {nodes_file: \"" +
            (data / "sequences/neohookean/s1/forces-vertices-remeshed.npy").string() +
            "\"}\n    total_force: [0.3, -0.5, -0.8]\n",
        "static-frame.yaml", ".");
  }
  label = "cylinder3800-stand-in";
  return loadSceneFromString(
      "mesh: {generator: cylinder, radius: 0.015, length: 0.18, target_nodes: 3800}\n" + law +
          "fixed:\n  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
          "loads:\n  - region: {half_space: {point: [0, 0, 0.1799], normal: [0, 0, 1]}}\n"
          "    total_force: [0.01, 0.01, 0]\n",
      "static-frame.yaml", ".");
}

const StaticFrame& staticFrame() {
  static const StaticFrame frame = [] {
    std::string label;
    StaticFrame f{frameScene(label), {}, label};
    StaticSolver newton(f.scene.model, makeLinearSolver("cholmod"), f.scene.statics);
    f.x = f.scene.model.restPositions();
    newton.solve(f.scene.model, 1.0, f.x);
    return f;
  }();
  return frame;
}

void counters(benchmark::State& st, const StaticFrame& f) {
  addMeshCounters(st, f.scene.model);
  st.SetLabel(f.label);
}

void BM_ForceAssembly(benchmark::State& st) {
  const StaticFrame& f = staticFrame();
  Eigen::VectorXd force;
  for (auto _ : st) {
    f.scene.model.internalForces(1.0, f.x, force);
    benchmark::DoNotOptimize(force.data());
  }
  counters(st, f);
}

void BM_StiffnessAssembly(benchmark::State& st) {
  const StaticFrame& f = staticFrame();
  Eigen::VectorXd force;
  SparseMatrix K = f.scene.model.pattern->emptyMatrix();
  for (auto _ : st) {
    f.scene.model.internalForcesAndStiffness(1.0, f.x, force, K);
    benchmark::DoNotOptimize(K.valuePtr());
  }
  counters(st, f);
}

// K with the Dirichlet dofs eliminated, as FrozenTangent::buildStatic factorises it.
SparseMatrix eliminatedStiffness(const StaticFrame& f) {
  Eigen::VectorXd force;
  SparseMatrix K = f.scene.model.pattern->emptyMatrix();
  f.scene.model.internalForcesAndStiffness(1.0, f.x, force, K);
  f.scene.model.dirichlet.eliminateMatrix(K);
  return K;
}

// threads 0: CHOLMOD's numeric factorisation; N >= 1: bcassim's (SupernodalCholesky) on N threads.
void BM_Factorize(benchmark::State& st, int threads) {
  const StaticFrame& f = staticFrame();
  const SparseMatrix K = eliminatedStiffness(f);
  CholeskyFactor factor;
  factor.analyzePattern(K);
  for (auto _ : st) {
    if (threads == 0)
      factor.factorizeWithCholmod(K);
    else
      factor.factorize(K, threads);
  }
  Eigen::VectorXd b = Eigen::VectorXd::Ones(K.rows()), y;
  factor.solve(b, y);
  st.counters["rel_residual"] = (K * y - b).norm() / b.norm();
  counters(st, f);
  st.counters["dofs"] = static_cast<double>(K.rows());
  st.counters["nnz_K"] = static_cast<double>(K.nonZeros());
  st.counters["nnz_L"] = static_cast<double>(factor.factorNonZeros());
}

// threads 0: one sweep on this thread; N >= 1: the elimination tree's subtrees on N threads.
void BM_Solve(benchmark::State& st, bool single, int threads) {
  const StaticFrame& f = staticFrame();
  const SparseMatrix K = eliminatedStiffness(f);
  CholeskyFactor factor;
  factor.factorize(K);
  CholeskyFactor::Workspace work;
  work.setThreads(threads);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(K.rows()), y;
  for (auto _ : st) {
    if (single)
      factor.solveSinglePrecision(b, y, work);
    else
      factor.solve(b, y, work);
    benchmark::DoNotOptimize(y.data());
  }
  counters(st, f);
  st.counters["rel_residual"] = (K * y - b).norm() / b.norm();
}

// From the equilibrium under the tool force towards the one under a force 10 % larger, with the
// tangent of the first: one linearised step (maxIterations 1, double precision: what a sigma point
// costs with tangent: mean), or the mean's equilibrium by chord iterations (Anderson-mixed, single
// precision, to the 1e-8 tolerance of the registration: what a frame's end costs).
// threads: as StaticSolver::chordSolve's (0: serial kernels; N: split over N threads).
void BM_Chord(benchmark::State& st, int maxIterations, bool singlePrecision, int threads) {
  const StaticFrame& f = staticFrame();
  bcassim::Scene scene = f.scene;
  const MechanicalState at{f.x, Eigen::VectorXd::Zero(f.x.size()), 1.0};
  const auto tangent = FrozenTangent::buildStatic(scene.model, at);
  for (auto& load : scene.model.loads) load.forcePerNode *= 1.1;
  StaticSolver chord(scene.model, makeLinearSolver("cholmod"), scene.statics);
  Eigen::VectorXd x;
  StaticReport report;
  for (auto _ : st) {
    x = f.x;
    report =
        chord.chordSolve(scene.model, 1.0, x, *tangent, maxIterations, singlePrecision, threads);
    benchmark::DoNotOptimize(x.data());
  }
  counters(st, f);
  st.counters["iterations"] = report.iterations;
  st.counters["converged"] = report.converged ? 1 : 0;
}

void registerAll() {
  using benchmark::kMillisecond;
  benchmark::RegisterBenchmark("static_frame/force_assembly", BM_ForceAssembly)->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/force_stiffness_assembly", BM_StiffnessAssembly)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/factorize", BM_Factorize, 0)->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/factorize_split_1_thread", BM_Factorize, 1)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/factorize_split_2_threads", BM_Factorize, 2)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/solve_double", BM_Solve, false, 0)->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/solve_single", BM_Solve, true, 0)->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/solve_single_split_1_thread", BM_Solve, true, 1)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/solve_single_split_2_threads", BM_Solve, true, 2)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/chord_step", BM_Chord, 1, false, 0)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/chord_solve", BM_Chord, 30, true, 0)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/chord_solve_split_1_thread", BM_Chord, 30, true, 1)
      ->Unit(kMillisecond);
  benchmark::RegisterBenchmark("static_frame/chord_solve_split_2_threads", BM_Chord, 30, true, 2)
      ->Unit(kMillisecond);
}

}  // namespace
}  // namespace bcassim::bench

int main(int argc, char** argv) {
  bcassim::bench::registerAll();
  return bcassim::bench::runBenchmarks(argc, argv);
}
