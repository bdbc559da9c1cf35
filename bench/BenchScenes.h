// Scenes shared by the benchmark programs: the thesis cylinder (both ends fixed, periodic lateral
// load at mid-length) and the 15x3x3 cm beam of thesis Table 2.1 (one end fixed, bending load on
// the bottom face), plus helpers that rebuild the implicit-Euler system matrix of eq. 2.16 so the
// factorisation and the solve can be timed on their own.
#pragma once
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/materials/Material.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim::bench {

inline std::vector<int> nodesWhere(const TetMesh& mesh, const std::function<bool(const Vec3&)>& p) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    if (p(mesh.V.row(i).transpose())) out.push_back(static_cast<int>(i));
  return out;
}

struct Scene {
  MechanicalModel model;
  double dt = 0.01;  // s
  std::string label;
};

// Common time-integration settings of every benchmark scene (thesis-like values).
inline constexpr double kDensity = 1000.0;          // kg/m^3
inline constexpr double kRayleighMass = 0.1;        // 1/s
inline constexpr double kRayleighStiffness = 0.01;  // s
inline constexpr double kDt = 0.01;                 // s

// Cylinder r 1.5 cm, L 18 cm along z, StVK E 8 kPa nu 0.49 (thesis §3.4), nodes at z = 0 and
// z = L fixed, 0.2 N (total) sine load along y (period 1 s) on the outer-surface nodes of the
// layer nearest mid-length with y > 0. targetNodes 915 gives the thesis' 930-node mesh.
// patchTets > 1: mean dilatation over patches of that many tets.
inline Scene makeCylinderScene(int targetNodes, const std::string& material = "stvk",
                               int patchTets = 1) {
  constexpr double r = 0.015, L = 0.18;
  auto mesh = std::make_shared<const TetMesh>(makeCylinderMesh(r, L, targetNodes));
  MechanicalModel model = makeMechanicalModel(mesh, {makeMaterial(material, 8000.0, 0.49)},
                                              kDensity, MassKind::Lumped, patchTets);
  const double tol = 1e-9;
  DirichletRegion ends;
  ends.nodes = nodesWhere(*mesh, [&](const Vec3& p) { return p.z() < tol || p.z() > L - tol; });
  model.dirichlet = DirichletConditions({ends}, *model.pattern);

  double zMid = 0, best = 1e300;  // z of the node layer nearest L/2
  for (Eigen::Index i = 0; i < mesh->numNodes(); ++i)
    if (std::abs(mesh->V(i, 2) - 0.5 * L) < best)
      best = std::abs(mesh->V(i, 2) - 0.5 * L), zMid = mesh->V(i, 2);
  NodalLoad load;
  load.nodes = nodesWhere(*mesh, [&](const Vec3& p) {
    return std::abs(p.z() - zMid) < tol && std::hypot(p.x(), p.y()) > 0.99 * r && p.y() > 0;
  });
  load.forcePerNode = Vec3(0, 0.2 / static_cast<double>(load.nodes.size()), 0);
  load.profile = {TimeProfile::Kind::Sine, 1.0, 0.0};
  model.loads.push_back(load);
  model.rayleighMass = kRayleighMass;
  model.rayleighStiffness = kRayleighStiffness;
  return {std::move(model), kDt, "cylinder" + std::to_string(targetNodes)};
}

// Thesis Table 2.1 beam: 15 x 3 x 3 cm along x, ~targetTets tets, E 1.542 MPa nu 0.49 (the
// thesis' Neo-Hookean-equivalent modulus), x = 0 face fixed, 5 N (total) downward load spread
// over the nodes of the bottom face z = 0.
inline Scene makeBeamScene(int targetTets, const std::string& material) {
  const Vec3 size(0.15, 0.03, 0.03);
  auto mesh = std::make_shared<const TetMesh>(makeBoxMeshWithTargetTets(size, targetTets));
  MechanicalModel model = makeMechanicalModel(mesh, {makeMaterial(material, 1.542e6, 0.49)},
                                              kDensity, MassKind::Lumped);
  const double tol = 1e-9;
  DirichletRegion fixed;
  fixed.nodes = nodesWhere(*mesh, [&](const Vec3& p) { return p.x() < tol; });
  model.dirichlet = DirichletConditions({fixed}, *model.pattern);
  NodalLoad load;
  load.nodes = nodesWhere(*mesh, [&](const Vec3& p) { return p.z() < tol && p.x() > tol; });
  load.forcePerNode = Vec3(0, 0, -5.0 / static_cast<double>(load.nodes.size()));
  model.loads.push_back(load);
  model.rayleighMass = kRayleighMass;
  model.rayleighStiffness = kRayleighStiffness;
  return {std::move(model), kDt, "beam" + std::to_string(targetTets) + "/" + material};
}

// A smoothly bent configuration of the beam (tip lowered by 3 cm, cross sections rotated with
// the centre line, det F > 0 everywhere) so that the nonlinear kernels see a real deformation.
inline Eigen::VectorXd bentBeamPositions(const MechanicalModel& model) {
  const double c = 0.03 / (0.15 * 0.15), zc = 0.015;
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < model.mesh->numNodes(); ++i) {
    const double X = model.mesh->V(i, 0), Z = model.mesh->V(i, 2);
    x(3 * i + 0) += 2.0 * c * X * (Z - zc);
    x(3 * i + 2) -= c * X * X;
  }
  return x;
}

// Runs `steps` implicit-Euler steps with a direct solver from rest, giving a deformed, moving
// state to benchmark from.
inline MechanicalState warmedUpState(const Scene& scene, int steps) {
  MechanicalState s = scene.model.restState();
  ImplicitEuler euler(scene.model, makeLinearSolver("cholmod"), {scene.dt});
  for (int i = 0; i < steps; ++i) euler.step(scene.model, s);
  return s;
}

// The eq. 2.16 system of one implicit-Euler step from state s, Dirichlet rows eliminated, exactly
// as ImplicitEuler::step forms it (A = (1 + dt zM) M + (dt zK + dt^2) K).
inline void implicitEulerSystem(const Scene& scene, const MechanicalState& s, SparseMatrix& A,
                                Eigen::VectorXd& rhs) {
  const MechanicalModel& m = scene.model;
  const double h = scene.dt;
  Eigen::VectorXd fint, fext, Mv;
  m.internalForcesAndStiffness(s.t, s.x, fint, A);
  m.externalForces(s.t + h, fext);
  const Eigen::VectorXd Kv = A * s.v;
  m.mass.multiply(s.v, Mv);
  rhs = h * (fext - fint - m.rayleighMass * Mv - (m.rayleighStiffness + h) * Kv);
  A.coeffs() *= h * m.rayleighStiffness + h * h;
  m.mass.addTo(*m.pattern, 1.0 + h * m.rayleighMass, A);
  if (!m.dirichlet.empty()) {
    const Eigen::VectorXd rest = m.restPositions();
    const Eigen::VectorXd target = m.dirichlet.targetPositions(rest, s.t + h);
    Eigen::VectorXd known(target.size());
    for (Eigen::Index k = 0; k < target.size(); ++k) {
      const int d = m.dirichlet.constrainedDofs()[k];
      known(k) = (target(k) - s.x(d)) / h - s.v(d);
    }
    m.dirichlet.eliminate(A, rhs, known);
  }
}

inline void addMeshCounters(benchmark::State& state, const MechanicalModel& model) {
  state.counters["nodes"] = static_cast<double>(model.mesh->numNodes());
  state.counters["tets"] = static_cast<double>(model.mesh->numTets());
}

// Threads for TBB-parallel code (BCASSIM_BENCH_THREADS, default 1: the targets are per core).
// CHOLMOD's OpenMP regions ask for 4 threads whatever OMP_NUM_THREADS says; scripts/bench.sh caps
// them with OMP_THREAD_LIMIT (read by libgomp at load time, so it cannot be set from here).
inline int benchThreads() {
  const char* env = std::getenv("BCASSIM_BENCH_THREADS");
  const int n = env ? std::atoi(env) : 1;
  return n > 0 ? n : 1;
}

inline int runBenchmarks(int argc, char** argv) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<std::size_t>(benchThreads()));
  benchmark::AddCustomContext("bcassim_threads", std::to_string(benchThreads()));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace bcassim::bench
