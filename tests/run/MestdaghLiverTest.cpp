// Verification against another solver (../shared/data/mestdagh-liver, made with FEniCS): static
// Neo-Hookean and linear solves of mesh-default under the true tool forces, read through a scene
// (nodes_file regions, total_force_frames), reproduce the published positions. Skipped when the
// data are absent.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bcassim/io/IndexListReader.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// $BCASSIM_DATA (relative to the source tree when relative), else <source>/../shared/data, with
// the benchmark in it; empty when absent.
fs::path mestdaghDir() {
  fs::path dir = fs::path(BCASSIM_SOURCE_DIR) / ".." / "shared" / "data";
  if (const char* env = std::getenv("BCASSIM_DATA"); env && *env) {
    dir = env;
    if (dir.is_relative()) dir = fs::path(BCASSIM_SOURCE_DIR) / dir;
  }
  dir /= "mestdagh-liver";
  return fs::is_directory(dir) ? dir : fs::path();
}

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

}  // namespace
}  // namespace bcassim
