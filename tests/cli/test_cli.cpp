// The bcassim executable as a user meets it: one-line errors with file, line and key and exit
// code 2 for bad scenes, a successful run, mesh info and tetra, and --version.
#include <gtest/gtest.h>

#include <vector>

#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::runBcassim;
using test::writeText;

const char* kMesh = "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n";

// Writes `yaml` as scene.yaml in a fresh directory and runs `bcassim simulate` on it.
test::CliResult simulateScene(const std::string& yaml) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml", yaml);
  return runBcassim(dir, "simulate scene.yaml --out out --quiet");
}

using test::expectSceneInputError;

TEST(Cli, UnknownKey) {
  expectSceneInputError(std::string(kMesh) + "material:\n  model: stvk\n  youngs_modulus: 8000\n",
                        "scene.yaml:4: unknown key 'youngs_modulus' in material; expected one of "
                        "model, young_modulus, poisson_ratio, c10, c01, kappa, mu, alpha");
}

TEST(Cli, WrongType) {
  expectSceneInputError(std::string(kMesh) + "time:\n  dt: fast\n",
                        "scene.yaml:3: time.dt: expected a number in seconds, got 'fast'");
}

TEST(Cli, MissingMeshFile) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml", "# liver\nmesh:\n  file: ../data/nothere.vtk\n");
  const test::CliResult r = runBcassim(dir, "simulate scene.yaml --out out");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: scene.yaml:3: mesh.file: cannot open '" +
                       (dir.parent_path() / "data" / "nothere.vtk").string() + "'\n");
}

TEST(Cli, NonPositiveTimeStep) {
  expectSceneInputError(std::string(kMesh) + "time: {dt: 0, steps: 10}\n",
                        "scene.yaml:2: time.dt: must be > 0 seconds, got 0");
}

TEST(Cli, RegionSelectingNothing) {
  expectSceneInputError(std::string(kMesh) +
                            "fixed:\n  - region:\n      sphere: {center: [1, 1, 1], "
                            "radius: 0.01}\n",
                        "scene.yaml:4: fixed[0].region: selects no node of the mesh");
}

TEST(Cli, InvalidYaml) {
  expectSceneInputError(std::string(kMesh) + "time: {dt: 0.01\nsteps: 3\n",
                        "scene.yaml:3: invalid YAML: end of map flow not found");
}

TEST(Cli, PoissonRatioOutOfRange) {
  expectSceneInputError(std::string(kMesh) + "material: {poisson_ratio: 0.5}\n",
                        "scene.yaml:2: material.poisson_ratio: must be in (-1, 0.5), got 0.5");
}

TEST(Cli, FailedRunIsANumericalErrorWithExitCode3) {
  // One Newton iteration cannot balance a load that bends the beam a lot.
  const test::CliResult r =
      simulateScene(std::string(kMesh) +
                    "integrator: {type: static, max_iterations: 1}\ntime: {dt: 1, steps: 1}\n"
                    "fixed:\n  - region: {box: {min: [-1, -1, -1], max: [0.0001, 1, 1]}}\n"
                    "loads:\n  - region: {box: {min: [0.0999, -1, -1], max: [1, 1, 1]}}\n"
                    "    total_force: [0, 0, 0.5]\n");
  EXPECT_EQ(r.exitCode, 3);
  EXPECT_EQ(test::countLines(r.err), 1);
  EXPECT_EQ(r.err.rfind("bcassim: error: scene.yaml: step 1 (t = 1 s): Newton did not converge in "
                        "1 iteration (residual ",
                        0),
            0u)
      << r.err;
}

TEST(Cli, MissingSceneFile) {
  const auto dir = freshDir();
  const test::CliResult r = runBcassim(dir, "simulate none.yaml");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: none.yaml: cannot open file\n");
}

TEST(Cli, BadArgumentsAreOneLineInputErrors) {
  const auto dir = freshDir();
  const test::CliResult r = runBcassim(dir, "simulate");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(test::countLines(r.err), 1);
  EXPECT_EQ(r.err.rfind("bcassim: error: ", 0), 0u);
}

TEST(Cli, SimulateWritesOutputsAndSummary) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml", std::string(kMesh) +
                                    "time: {steps: 4}\nfixed:\n  - region: {nodes: [0, 5]}\n"
                                    "markers:\n  - points: [[0.1, 0.02, 0.02]]\n");
  const test::CliResult r = runBcassim(dir, "simulate scene.yaml --out results");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "results" / "simulation.pvd"));
  EXPECT_TRUE(std::filesystem::exists(dir / "results" / "markers.csv"));
  EXPECT_NE(r.out.find("scene scene.yaml: 20 nodes, 24 tets, 1 markers, 0 springs, 4 steps"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("base: 4 steps"), std::string::npos) << r.out;
}

TEST(Cli, MeshInfoReportsCountsAndQuality) {
  const auto dir = freshDir();
  writeTetMesh((dir / "box.vtk").string(), makeBoxMesh(Vec3(0.03, 0.02, 0.01), 3, 2, 1));
  const test::CliResult r = runBcassim(dir, "mesh info box.vtk");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("nodes: 24\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tets: 36\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("regions: 0 (36 tets)\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("volume: 6e-06 m^3\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("inverted tets: 0\n"), std::string::npos) << r.out;
}

TEST(Cli, MeshInfoOnAMissingFile) {
  const auto dir = freshDir();
  const test::CliResult r = runBcassim(dir, "mesh info none.vtk");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: none.vtk: cannot open file\n");
}

// A sphere of radius 40 mm with a cap cut off (a hole larger than --max-hole-edges) and, for
// `open`, its upper half gone (a bowl), as a millimetre .obj in `dir`.
void writeBrokenSphere(const std::filesystem::path& file, bool open) {
  const TriMesh sphere = makeIcosphereSurface(40.0, 3);
  std::vector<int> kept;
  for (Eigen::Index f = 0; f < sphere.F.rows(); ++f) {
    double z = 0;
    for (int c = 0; c < 3; ++c) z += sphere.V(sphere.F(f, c), 2) / 3;
    if (z < (open ? 0.0 : 36.0)) kept.push_back(static_cast<int>(f));
  }
  TriMesh broken;
  broken.V = sphere.V;
  broken.F.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
    broken.F.row(static_cast<Eigen::Index>(i)) = sphere.F.row(kept[i]);
  writeSurface(file.string(), broken);
}

TEST(Cli, MeshTetraMeshesASurfaceWithALargeHole) {
  const auto dir = freshDir();
  writeBrokenSphere(dir / "ball.obj", false);
  const test::CliResult r =
      runBcassim(dir, "mesh tetra ball.obj --nodes 300 --max-hole-edges 8 --out m");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("repairs: meshed from the ray-vote inside test (a border loop of"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("wrote m/mesh.vtu and m/surface.vtp"), std::string::npos) << r.out;
  const test::CliResult info = runBcassim(dir, "mesh info m/mesh.vtu");
  EXPECT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("inverted tets: 0\n"), std::string::npos) << info.out;
}

TEST(Cli, MeshTetraRefusesAnOpenBowlInOneLine) {
  const auto dir = freshDir();
  writeBrokenSphere(dir / "bowl.obj", true);
  const test::CliResult r = runBcassim(dir, "mesh tetra bowl.obj --max-hole-edges 8 --out m");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err.rfind("bcassim: error: bowl.obj: a border loop of ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("; nor does it enclose a clear inside (votes 4 to 3 at "), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "m" / "mesh.vtu"));
}

TEST(Cli, MeshTetraRefusesANonPositiveNodeCountOrHoleLimitInOneLine) {
  const auto dir = freshDir();
  writeBrokenSphere(dir / "ball.obj", false);
  for (const char* option : {"--nodes", "--max-hole-edges"}) {
    SCOPED_TRACE(option);
    const test::CliResult r =
        runBcassim(dir, std::string("mesh tetra ball.obj --out m ") + option + " 0");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, std::string("bcassim: error: ") + option +
                         ": expected a number > 0, got '0' (see 'bcassim --help')\n");
  }
}

TEST(Cli, Version) {
  const auto dir = freshDir();
  const test::CliResult r = runBcassim(dir, "--version");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.out.rfind("bcassim ", 0), 0u);
}

}  // namespace
}  // namespace bcassim
