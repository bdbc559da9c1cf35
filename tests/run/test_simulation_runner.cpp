// Running scenes end to end through the library: files written, frames, tracks, timings,
// static equilibrium, steps halved where they fail, and variant comparison.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::countLines;
using test::countOccurrences;
using test::freshDir;
using test::readText;

// A 10 cm cantilever (4 x 1 x 1 cells) clamped at x = 0, pulled up at its free end.
const std::string kBeam = R"(
mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}
material: {model: stvk, young_modulus: 10000, poisson_ratio: 0.3}
fixed:
  - region: {box: {min: [-1, -1, -1], max: [0.0001, 1, 1]}}
loads:
  - region: {box: {min: [0.0999, -1, -1], max: [1, 1, 1]}}
    total_force: [0, 0, 0.01]
markers:
  - region: {box: {min: [0.0999, -1, -1], max: [1, 1, 1]}}
  - points: [[0.05, 0.01, 0.01]]
)";

// A run stopped at step 37 (the last checkpoint at step 30) and resumed writes the same files as
// one that never stopped: tracks and validation byte for byte (direct solver: the same
// arithmetic), the .pvd with the same frames, one timing row per step.
TEST(SimulationRunner, ResumedRunWritesWhatAnUninterruptedOneWrites) {
  const auto dir = freshDir();
  const Scene scene = loadSceneFromString(kBeam + R"(
time: {dt: 0.01, steps: 50}
output: {every: 10}
solver: {type: cholmod}
validation_points: {nodes: all}
)",
                                          "beam.yaml", dir.string());
  runSimulation(scene, (dir / "whole").string());
  struct Stop {};
  EXPECT_THROW(runSimulation(scene, (dir / "stopped").string(),
                             [](const RunProgress& p) {
                               if (p.step == 37) throw Stop{};
                             }),
               Stop);
  // Rows past the checkpoint (step 30) are on disk too; resuming cuts them off.
  EXPECT_EQ(countLines(readText(dir / "stopped" / "timing.csv")), 1 + 37);
  const SimulationResult r = runSimulation(scene, (dir / "stopped").string(), {}, true);
  EXPECT_EQ(r.runs[0].frames, 6);
  for (const char* f : {"markers.csv", "validation.csv", "simulation.pvd"})
    EXPECT_EQ(readText(dir / "stopped" / f), readText(dir / "whole" / f)) << f;
  EXPECT_EQ(countLines(readText(dir / "stopped" / "timing.csv")), 1 + 50);
  EXPECT_EQ(readText(dir / "stopped" / "simulation_000005.vtu"),
            readText(dir / "whole" / "simulation_000005.vtu"));

  // A checkpoint belongs to its scene.
  const Scene other =
      loadSceneFromString(kBeam + "time: {dt: 0.02, steps: 50}\n", "other.yaml", dir.string());
  try {
    runSimulation(other, (dir / "stopped").string(), {}, true);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "stopped" / "checkpoint.bin").string() +
                  ": written for another scene (nodes 20 tets 24 dt 0.01 implicit-euler); this "
                  "scene is nodes 20 tets 24 dt 0.02 implicit-euler");
  }
  try {
    runSimulation(scene, (dir / "nothing").string(), {}, true);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "nothing" / "checkpoint.bin").string() +
                                         ": no checkpoint to resume from (run without --resume)");
  }
}

// One flipped byte in a real checkpoint (inside the positions) is refused on --resume, naming the
// CRC-32 of the damaged contents and the one written at the end.
TEST(SimulationRunner, ResumeFromADamagedCheckpointIsRefusedByItsChecksum) {
  const auto dir = freshDir();
  const Scene scene = loadSceneFromString(
      kBeam + "time: {dt: 0.01, steps: 20}\noutput: {every: 10}\n", "beam.yaml", dir.string());
  runSimulation(scene, dir.string());
  const std::string path = (dir / "checkpoint.bin").string();
  std::string bytes = readText(path);
  ASSERT_GT(bytes.size(), 400u);
  const auto crcOf = [](const std::string& b) {
    return static_cast<std::uint32_t>(
        ::crc32(0, reinterpret_cast<const Bytef*>(b.data()), static_cast<uInt>(b.size() - 5)));
  };
  const std::uint32_t written = crcOf(bytes);
  bytes[bytes.size() / 2] ^= 0x01;
  std::ofstream(path, std::ios::binary) << bytes;
  try {
    runSimulation(scene, dir.string(), {}, true);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              fmt::format("{}: damaged (checksum {:08x}); expected {:08x}, the CRC-32 written at "
                          "its end",
                          path, crcOf(bytes), written));
  }
}

TEST(SimulationRunner, WritesSeriesTracksAndTimings) {
  const auto dir = freshDir();
  const Scene scene = loadSceneFromString(kBeam + R"(
time: {dt: 0.01, steps: 7}
output: {every: 3}
springs:
  attachments: [{region: {box: {min: [0.05, -1, 0.0199], max: [0.05, 1, 1]}}}]
)",
                                          "beam.yaml", dir.string());
  std::vector<int> seen;
  const SimulationResult result = runSimulation(
      scene, (dir / "out").string(), [&](const RunProgress& p) { seen.push_back(p.stepsDone); });

  ASSERT_EQ(result.runs.size(), 1u);
  const RunResult& run = result.runs[0];
  EXPECT_EQ(run.steps, 7);
  // Steps 0, 3, 6 and the last one, 7.
  EXPECT_EQ(run.frames, 4);
  const std::string pvd = readText(dir / "out" / "simulation.pvd");
  EXPECT_EQ(countOccurrences(pvd, "part=\"0\""), 4);
  EXPECT_EQ(countOccurrences(pvd, "simulation_markers_"), 4);
  EXPECT_EQ(countOccurrences(pvd, "simulation_springs_"), 4);
  for (int f = 0; f < 4; ++f)
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / fmt::format("simulation_{:06}.vtu", f)));

  // 5 markers (4 end nodes + 1 point) after each of 7 steps, plus the header.
  const std::string markers = readText(dir / "out" / "markers.csv");
  EXPECT_EQ(countLines(markers), 1 + 7 * 5);
  EXPECT_EQ(markers.substr(0, markers.find('\n')), "time,marker,x,y,z");
  const std::string timing = readText(dir / "out" / "timing.csv");
  EXPECT_EQ(countLines(timing), 1 + 7);
  EXPECT_EQ(timing.substr(0, timing.find('\n')),
            "step,time_s,assembly_ms,solve_ms,total_ms,linear_iterations,retries");

  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
  EXPECT_GT(run.maxMarkerDisplacement, 0.0);
  EXPECT_GT(run.meanStepMs, 0.0);
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "variants.csv"));
}

TEST(SimulationRunner, StaticEquilibriumBendsTheBeamTowardsTheLoad) {
  const auto dir = freshDir();
  const Scene scene = loadSceneFromString(kBeam + R"(
integrator: {type: static, load_steps: 2}
time: {dt: 1, steps: 2}
output: {pvd: false}
)",
                                          "beam.yaml", dir.string());
  const SimulationResult result = runSimulation(scene, dir.string());
  EXPECT_EQ(result.runs[0].frames, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "simulation.pvd"));
  // Last line: the mid-beam point marker (index 4) at the final time moved up in z.
  const std::string markers = readText(dir / "markers.csv");
  const std::string last = markers.substr(markers.rfind('\n', markers.size() - 2) + 1);
  EXPECT_EQ(last.substr(0, 4), "2,4,");
  const double z = std::stod(last.substr(last.rfind(',') + 1));
  EXPECT_GT(z, 0.01 + 1e-5);
  EXPECT_EQ(readText(dir / "timing.csv").substr(0, 46),
            "step,time_s,total_ms,newton_iterations,retries");
}

// A static run resumed from its checkpoint ramps the next step's loads from the checkpoint's, as
// the run that never stopped does: the same markers, byte for byte.
TEST(SimulationRunner, ResumedStaticRunRampsFromTheCheckpointsLoad) {
  const auto dir = freshDir();
  std::string yaml = kBeam + R"(
integrator: {type: static, load_steps: 3}
time: {dt: 1, steps: 4}
output: {every: 2, pvd: false}
)";
  yaml.replace(yaml.find("total_force: [0, 0, 0.01]"), 25,
               "total_force: [0, 0, 0.01]\n    profile: {kind: ramp, period: 4}");
  const Scene scene = loadSceneFromString(yaml, "beam.yaml", dir.string());
  runSimulation(scene, (dir / "whole").string());
  struct Stop {};
  EXPECT_THROW(runSimulation(scene, (dir / "stopped").string(),
                             [](const RunProgress& p) {
                               if (p.step == 3) throw Stop{};
                             }),
               Stop);
  runSimulation(scene, (dir / "stopped").string(), {}, true);
  EXPECT_EQ(readText(dir / "stopped" / "markers.csv"), readText(dir / "whole" / "markers.csv"));
}

// The rows of timing.csv after its header, split at commas.
std::vector<std::vector<std::string>> timingRows(const std::filesystem::path& dir) {
  std::istringstream in(readText(dir / "timing.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    rows.push_back(fields);
  }
  return rows;
}

// A zero load is solved at once (it used to fail with "residual 2.6e-12 N after 50 Newton
// iterations"), a 1e-9 N one in one or two iterations (not 50 spent on round-off).
TEST(SimulationRunner, StaticScenesUnderZeroAndTinyLoadsConvergeAtOnce) {
  for (const char* load : {"0", "1.0e-9"}) {
    SCOPED_TRACE(load);
    const auto dir = freshDir();
    std::string yaml = kBeam + R"(
integrator: {type: static}
time: {dt: 1, steps: 3}
output: {pvd: false}
)";
    yaml.replace(yaml.find("total_force: [0, 0, 0.01]"), 25,
                 fmt::format("total_force: [0, 0, {}]", load));
    runSimulation(loadSceneFromString(yaml, "beam.yaml", dir.string()), dir.string());
    const auto rows = timingRows(dir);
    ASSERT_EQ(rows.size(), 3u);
    for (const auto& row : rows) {
      EXPECT_LE(std::stoi(row[3]), 2);  // newton_iterations
      EXPECT_EQ(row[4], "0");           // retries
    }
  }
}

// One tet (legs 10 cm) whose base is fixed and whose apex a load pushes through the base in one
// step of 10 ms: the apex (lumped mass m = 41.7 g, stiffness along the normal k = 22.4 N/m at
// E = 1 kPa, nu = 0.3) would move u = h^2 f / (m + h^2 k) = 1.1 times the height, det F = -0.1;
// two steps of 5 ms keep it above the base. Corotational: the linear law's response along the
// normal, but an inverted tet fails it (the linear law takes it).
const std::string kFlattenedTet = R"(
mesh: {file: tet.vtk}
material: {model: corotational, young_modulus: 1000, poisson_ratio: 0.3}
time: {dt: 0.01, steps: 1}
fixed: [{region: {box: {min: [-1, -1, -1], max: [1, 1, 0.001]}}}]
loads: [{region: {box: {min: [-1, -1, 0.099], max: [1, 1, 1]}}, total_force: [0, 0, -48.3013]}]
validation_points: {nodes: all}
output: {pvd: false}
)";
void writeTetMesh(const std::filesystem::path& dir) {
  test::writeText(dir / "tet.vtk",
                  "# vtk DataFile Version 2.0\ntet\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                  "POINTS 4 double\n0 0 0\n0.1 0 0\n0 0.1 0\n0 0 0.1\n"
                  "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n");
}

TEST(SimulationRunner, InvertingStepIsHalvedAndCountedInTiming) {
  const auto dir = freshDir();
  writeTetMesh(dir);
  const Scene scene = loadSceneFromString(kFlattenedTet, "tet.yaml", dir.string());
  runSimulation(scene, (dir / "out").string());
  const auto rows = timingRows(dir / "out");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0][6], "1");  // retries
  // The final state, from validation.csv (every node after step 1): no tet inverted.
  std::istringstream in(readText(dir / "out" / "validation.csv"));
  Eigen::VectorXd x = scene.model.restPositions();
  std::string line;
  while (std::getline(in, line)) {
    double t, px, py, pz;
    int node;
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%lf,%lf", &t, &node, &px, &py, &pz) == 5 && t > 0)
      x.segment<3>(3 * node) = Vec3(px, py, pz);
  }
  EXPECT_EQ(scene.model.elasticity.countInverted(x), 0);
  EXPECT_GT(x(11), 0.0);  // the apex still above the base
  EXPECT_LT(x(11), 0.1 - 0.05);
}

TEST(SimulationRunner, StepFailingAtMinDtNamesStepTimeAndElement) {
  const auto dir = freshDir();
  writeTetMesh(dir);
  std::string yaml = kFlattenedTet;
  yaml.replace(yaml.find("time: {dt: 0.01, steps: 1}"), 26,
               "time: {dt: 0.01, steps: 1, min_dt: 0.01}");
  const Scene scene = loadSceneFromString(yaml, "tet.yaml", dir.string());
  try {
    runSimulation(scene, (dir / "out").string());
    ADD_FAILURE() << "no NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_EQ(std::string(e.what()),
              "tet.yaml: step 1 (t = 0 s): element 0 inverted (det F = -0.1) at the time step "
              "0.01 s (time.min_dt = 0.01 s allows no halving)");
  }
}

TEST(SimulationRunner, VariantsAreComparedWithTheBase) {
  const auto dir = freshDir();
  const Scene scene = loadSceneFromString(kBeam + R"(
time: {dt: 0.01, steps: 5}
output: {every: 5}
variants:
  - {name: same, material: {model: stvk}}
  - {name: linear, material: {model: linear}}
  - {name: soft, material: {young_modulus: 5000}}
)",
                                          "beam.yaml", dir.string());
  const SimulationResult result = runSimulation(scene, dir.string());
  ASSERT_EQ(result.runs.size(), 4u);
  EXPECT_EQ(result.runs[0].name, "base");
  EXPECT_EQ(result.runs[0].relativeDifferenceFinal, 0.0);
  EXPECT_EQ(result.runs[1].relativeDifferenceFinal, 0.0);  // same model, same numbers
  EXPECT_EQ(result.runs[1].relativeDifferenceAll, 0.0);
  EXPECT_GT(result.runs[2].relativeDifferenceFinal, 0.0);
  EXPECT_GT(result.runs[3].relativeDifferenceAll, 0.1);  // half the stiffness: far off
  EXPECT_GE(result.runs[3].relativeDifferenceAll, result.runs[3].relativeDifferenceFinal);
  EXPECT_TRUE(std::filesystem::exists(dir / "soft" / "simulation.pvd"));
  EXPECT_TRUE(std::filesystem::exists(dir / "linear" / "markers.csv"));
  const std::string csv = readText(dir / "variants.csv");
  EXPECT_EQ(countLines(csv), 5);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "name,max_rel_diff_final,max_rel_diff_all,mean_step_ms,max_marker_displacement_m");
  EXPECT_NE(csv.find("\nsame,0,0,"), std::string::npos);
}

}  // namespace
}  // namespace bcassim
