// Verification against another solver (../shared/data/mestdagh-liver, made with FEniCS): static
// Neo-Hookean and linear solves of mesh-default under the true tool forces, read through a scene
// (nodes_file regions, total_force_frames), reproduce the published positions. Skipped when the
// data are absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bcassim/io/IndexListReader.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/SharedData.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// The benchmark's directory under the shared data (support/SharedData.h); empty when absent.
fs::path mestdaghDir() { return test::sharedPath("mestdagh-liver"); }

// The fixed-vertex list without `skipped` (-1: none) written to dir/name; returns its path.
fs::path writeFixed(const fs::path& data, const fs::path& dir, const char* name, int skipped) {
  std::ofstream fixed(dir / name);
  for (int id : readIndexList((data / "mesh-default" / "dirichlet-vertices.npy").string()))
    if (id != skipped) fixed << id << '\n';
  return dir / name;
}

// Static solves of the first `frames` frames of sequences/<family>/<sequence> under `material`
// (a YAML flow map) with `fixed` held; expects the relative displacement error over all nodes,
// |u - u_true| / |u_true|, within `tolerance` on each frame and the solves to take
// `newtonIterations` each (0: not checked).
void expectFramesReproduced(const fs::path& data, const fs::path& dir, const std::string& family,
                            const char* sequence, const std::string& material,
                            const fs::path& fixed, int frames, double tolerance,
                            int newtonIterations) {
  SCOPED_TRACE(family + "/" + sequence);
  const fs::path seq = data / "sequences" / family / sequence;
  const std::string yaml = "mesh: {file: " + (data / "mesh-default" / "liver.msh").string() +
                           "}\n"
                           "material: " +
                           material +
                           "\n"
                           "integrator: {type: static, tolerance: 1.0e-12}\n"
                           "time: {dt: 1, steps: " +
                           std::to_string(frames) +
                           "}\n"
                           "fixed:\n"
                           "  - region: {nodes_file: " +
                           fixed.string() +
                           "}\n"
                           "loads:\n"
                           "  - region: {nodes_file: " +
                           (seq / "tool-vertices-default.txt").string() +
                           "}\n"
                           "    total_force_frames: " +
                           (seq / "true-forces.npy").string() + "\n";
  const Scene scene = loadSceneFromString(yaml, "verify.yaml", dir.string());
  const NpyArray truth = readNpy((seq / "positions-default.npy").string());
  ASSERT_EQ(truth.shape.size(), 3u);
  const Eigen::Index n = 3 * scene.model.mesh->numNodes();
  ASSERT_EQ(truth.shape[1] * truth.shape[2], n);

  StaticSolver solver(scene.model, makeLinearSolver("cholmod"), scene.statics);
  const Eigen::VectorXd rest = scene.model.restPositions();
  Eigen::VectorXd x = rest;
  for (int k = 1; k <= frames; ++k) {
    const StaticReport report = solver.solve(scene.model, k * scene.dt(), x);
    if (newtonIterations > 0) {
      EXPECT_EQ(report.iterations, newtonIterations) << "frame " << k - 1;
    }
    const Eigen::Map<const Eigen::VectorXd> expected(
        truth.values.data() + static_cast<std::ptrdiff_t>(k - 1) * n, n);
    const double error = (x - expected).norm() / (expected - rest).norm();
    EXPECT_LE(error, tolerance) << "frame " << k - 1;
  }
}

constexpr int kFrames = 3;

TEST(MestdaghLiver, StaticNeoHookeanSolvesReproduceTheFenicsPositions) {
  const fs::path data = mestdaghDir();
  if (data.empty()) GTEST_SKIP() << "mestdagh-liver data not found (set BCASSIM_DATA)";
  const fs::path dir = test::freshDir();
  // The README's quirk: vertex 756 is in the list but moves in the true positions; the other
  // 105 do not. It is left free.
  const fs::path fixed = writeFixed(data, dir, "fixed-without-756.txt", 756);
  for (const char* sequence : {"s1", "s3"})
    expectFramesReproduced(data, dir, "neohookean", sequence,
                           "{model: neohookean, young_modulus: 4500, poisson_ratio: 0.49}", fixed,
                           kFrames, 1e-6, 0);
}

// The linear family's truths of s1 and s3 have inverted tets in every frame (1 and 2 of 10,703):
// the linear law takes them, and its quadratic energy makes each frame one Newton iteration. In
// this family vertex 756 stays where it is, with the other 105 of the list: all are fixed. Its
// constants are not in the data README: E = 20 kPa, nu = 0.45 (the original repository's SOFA
// example) reproduce the truths to 2-4e-5 on all 250 frames, not to 1e-6 (its stiffness matrix
// was assembled elsewhere; moving the mesh file's 6-digit coordinates by their rounding, 0.5 um,
// changes our solution by 8e-6), so 5e-5 here; E = 4500 Pa, nu = 0.49 is off by 2.5.
TEST(MestdaghLiver, StaticLinearSolvesReproduceTheFenicsPositionsThroughInvertedTets) {
  const fs::path data = mestdaghDir();
  if (data.empty()) GTEST_SKIP() << "mestdagh-liver data not found (set BCASSIM_DATA)";
  const fs::path dir = test::freshDir();
  const fs::path fixed = writeFixed(data, dir, "fixed.txt", -1);
  for (const char* sequence : {"s1", "s3"})
    expectFramesReproduced(data, dir, "linear", sequence,
                           "{model: linear, young_modulus: 20000, poisson_ratio: 0.45}", fixed,
                           kFrames, 5e-5, 1);
}

// Registration from the point clouds alone (examples/mestdagh-liver/register.yaml's setting), its
// first frames: from the zero prior the first frame's data move the force by 2.7 N. One analysis
// linearised about the rest shape lands two-thirds off (docs/results.md: 67 % on
// neohookean/s3); forecast again about its estimate (reforecasts), the frame lands within a few
// per cent (2.5 %), and the next frames stay there.
TEST(MestdaghLiver, ReforecastsRegisterTheFirstNeoHookeanFramesFromTheCloudsAlone) {
  const fs::path data = mestdaghDir();
  if (data.empty()) GTEST_SKIP() << "mestdagh-liver data not found (set BCASSIM_DATA)";
  const fs::path dir = test::freshDir();
  const fs::path seq = data / "sequences" / "neohookean" / "s3";
  const NpyArray truth = readNpy((seq / "true-forces.npy").string());
  constexpr int kSteps = 3;
  const auto scene = [&](int reforecasts) {
    const std::string force = ", stddev: 1, random_walk: 0.3}\n";
    return "mesh: {file: " + (data / "mesh-remeshed" / "liver.msh").string() +
           "}\n"
           "material: {model: neohookean, young_modulus: 4500, poisson_ratio: 0.49}\n"
           "integrator: {type: static, tolerance: 1.0e-6, max_iterations: 50}\n"
           "time: {dt: 1, steps: " +
           std::to_string(kSteps) + "}\nfixed:\n  - region: {nodes_file: " +
           (data / "mesh-remeshed" / "dirichlet-vertices.npy").string() +
           "}\nloads:\n  - region: {nodes_file: " +
           (seq / "forces-vertices-remeshed.npy").string() +
           "}\n"
           "    total_force: [0, 0, 0]\n"
           "    distribution: surface\n"
           "output: {pvd: false}\n"
           "assimilation:\n"
           "  threads: 2\n"
           "  tangent: mean\n"
           "  tangent_refresh_every: 2\n"
           "  tangent_background: true\n"
           "  reforecasts: " +
           std::to_string(reforecasts) +
           "\n  parameters:\n"
           "    - {name: Fx, force: {load: 0, component: x}, mean: 0" +
           force + "    - {name: Fy, force: {load: 0, component: y}, mean: 0" + force +
           "    - {name: Fz, force: {load: 0, component: z}, mean: 0" + force +
           "  observations:\n    point_cloud:\n      files: \"" + (seq / "pointclouds").string() +
           "/pc*.txt\"\n      surface: " +
           (data / "mesh-remeshed" / "matching-triangles.npy").string() +
           "\n      relinearizations: 8\n    sigma: 1.0e-3\n";
  };
  // The force error of each step's estimate (estimates.csv) against frame k - 1 of the data.
  const auto errors = [&](const fs::path& run) {
    std::vector<double> out;
    for (int k = 1; k <= kSteps; ++k) {
      Eigen::Vector3d estimate;
      for (int c = 0; c < 3; ++c)
        estimate(c) = test::estimateAt(run / "estimates.csv", std::string("F") + "xyz"[c], k);
      const Eigen::Map<const Eigen::Vector3d> f(truth.values.data() + 3 * (k - 1));
      out.push_back((estimate - f).norm() / f.norm());
    }
    return out;
  };
  for (const int reforecasts : {0, 2}) {
    SCOPED_TRACE("reforecasts " + std::to_string(reforecasts));
    const Scene s = loadSceneFromString(scene(reforecasts), "register.yaml", dir.string());
    const fs::path run = dir / ("reforecasts-" + std::to_string(reforecasts));
    runAssimilation(s, run.string());
    const std::vector<double> e = errors(run);
    ASSERT_EQ(e.size(), static_cast<size_t>(kSteps));
    std::cout << "[ mestdagh neohookean/s3 ] reforecasts " << reforecasts << ": force error "
              << 100 * e[0] << ", " << 100 * e[1] << ", " << 100 * e[2] << " %\n";
    if (reforecasts == 0) {
      EXPECT_GT(e[0], 0.4);
    } else {
      for (double error : e) EXPECT_LE(error, 0.05);
    }
  }
}

}  // namespace
}  // namespace bcassim
