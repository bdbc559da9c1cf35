// Unknown tool forces estimated from a partial point cloud (issue 14), end to end on a small
// cylinder in static mode: the truth is a static solve under a known force, the cloud the
// centroids of the deformed upper surface's triangles (no correspondences), and the filter starts
// from a zero force.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <sstream>

#include "bcassim/io/CsvTable.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/scene/ModelParameter.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// Both ends fixed, the load on a patch at mid-length; `load` and `extra` complete it.
std::string staticCylinder(const std::string& load, int steps, const std::string& extra) {
  return "mesh: {generator: cylinder, radius: 0.015, length: 0.18, target_nodes: 300}\n"
         "material: {model: neohookean, young_modulus: 8000, poisson_ratio: 0.45}\n"
         "integrator: {type: static, tolerance: 1.0e-10}\n"
         "time: {dt: 1, steps: " +
         std::to_string(steps) +
         "}\n"
         "fixed:\n"
         "  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
         "  - region: {half_space: {point: [0, 0, 0.1799], normal: [0, 0, 1]}}\n"
         "loads:\n"
         "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.075], max: [0.02, 0.02, "
         "0.105]}, direction: [0, -1, 0], max_angle_deg: 60}}\n"
         "    total_force: " +
         load + "\noutput: {pvd: false}\n" + extra;
}

// Solves the truth (force [0.01, -0.04, 0.005] N) and writes dir/cloud.txt: the deformed
// centroids of the boundary triangles whose rest centroid has y > 0 (the part a camera above
// sees), in m.
// With `footprint` (tilt u, tilt v, concentration), the force is shared as LoadFootprint says;
// `seenFromBelow`: the camera sees the triangles with y < 0 instead (the loaded patch's side).
void writeTruthCloud(const fs::path& dir, int steps,
                     const std::string& load = "[0.01, -0.04, 0.005]",
                     const Vec3& footprint = Vec3::Zero(), bool seenFromBelow = false) {
  Scene truth = loadSceneFromString(staticCylinder(load, steps, ""), "truth.yaml", dir.string());
  if (!footprint.isZero())
    for (int c = 0; c < 3; ++c)
      applyParameter(LoadFootprintTarget{0, c}, footprint(c), truth.model);
  StaticSolver solver(truth.model, makeLinearSolver("cholmod"), truth.statics);
  Eigen::VectorXd x = truth.model.restPositions();
  solver.solve(truth.model, 1.0, x);
  ASSERT_GT((x - truth.model.restPositions()).cwiseAbs().maxCoeff(), 2e-3);  // m: well seen

  // The part a camera above sees: triangles whose rest centroid has y > 0.
  const BoundarySurface boundary = extractBoundary(*truth.model.mesh);
  const Eigen::MatrixX3d& rest = truth.model.mesh->V;
  int points = 0;
  std::ofstream cloud(dir / "cloud.txt");
  for (Eigen::Index f = 0; f < boundary.F.rows(); ++f) {
    const Vec3 atRest =
        (rest.row(boundary.F(f, 0)) + rest.row(boundary.F(f, 1)) + rest.row(boundary.F(f, 2))) / 3;
    if ((atRest.y() <= 0) != seenFromBelow) continue;
    const Vec3 p = (x.segment<3>(3 * boundary.F(f, 0)) + x.segment<3>(3 * boundary.F(f, 1)) +
                    x.segment<3>(3 * boundary.F(f, 2))) /
                   3;
    cloud << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    ++points;
  }
  cloud.close();
  ASSERT_GT(points, 30);
}

TEST(PointCloudForce, StaticFramesRecoverAKnownToolForceFromAPartialCloud) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 6;
  const Vec3 force(0.01, -0.04, 0.005);  // N, as writeTruthCloud
  writeTruthCloud(dir, kSteps);
  // The same force every frame: one cloud file per step.
  for (int k = 1; k <= kSteps; ++k)
    fs::copy_file(dir / "cloud.txt", dir / ("pc" + std::to_string(k) + ".txt"));

  // tangent: mean linearises each sigma point's equilibrium about the analysed mean (one chord
  // step with its stiffness) and reaches the mean's by chord iterations: the same force.
  const std::vector<std::pair<std::string, std::string>> settings = {
      {"roukf", "own"}, {"ukf", "own"}, {"roukf", "mean"}};
  for (const auto& [filter, tangent] : settings) {
    const std::string name = filter + "-" + tangent;
    const Scene scene = loadSceneFromString(
        staticCylinder("[0, 0, 0]", kSteps,
                       "assimilation:\n  filter: " + filter + "\n  tangent: " + tangent +
                           "\n"
                           "  parameters:\n"
                           "    - {force: {load: 0, component: x}, mean: 0, stddev: 0.05, "
                           "random_walk: 0.001}\n"
                           "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.05, "
                           "random_walk: 0.001}\n"
                           "    - {force: {load: 0, component: z}, mean: 0, stddev: 0.05, "
                           "random_walk: 0.001}\n"
                           "  observations:\n"
                           "    point_cloud: {files: \"pc*.txt\"}\n"
                           "    sigma: 1.0e-5\n"),
        "estimation.yaml", dir.string());
    const AssimilationResult r = runAssimilation(scene, (dir / name).string());
    ASSERT_EQ(r.parameters.size(), 3u);
    const Vec3 estimate(r.parameters[0].mean, r.parameters[1].mean, r.parameters[2].mean);
    const double error = (estimate - force).norm() / force.norm();
    std::cout << "[ point-cloud force ] " << name << ": " << estimate.transpose() << " N (truth "
              << force.transpose() << "): " << 100 * error << " %, " << r.medianStepMs
              << " ms/frame\n";
    EXPECT_LE(error, 0.02) << name;
    EXPECT_EQ(r.observedSteps, kSteps) << name;
    EXPECT_TRUE(r.notices.empty()) << name << ": " << r.notices.front();
  }
}

// With tangent: mean the analysed mean's chord runs on every worker's thread (its force assembly
// and solves split in fixed chunks): 1, 2 and 3 threads give the same estimates bit for bit.
TEST(PointCloudForce, TheMeansChordGivesTheSameEstimatesOnAnyThreadCount) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 3;
  writeTruthCloud(dir, kSteps);
  for (int k = 1; k <= kSteps; ++k)
    fs::copy_file(dir / "cloud.txt", dir / ("pc" + std::to_string(k) + ".txt"));
  std::vector<AssimilationResult> results;
  for (int threads : {1, 2, 3}) {
    const Scene scene = loadSceneFromString(
        staticCylinder("[0, 0, 0]", kSteps,
                       "assimilation:\n  filter: roukf\n  tangent: mean\n  threads: " +
                           std::to_string(threads) +
                           "\n"
                           "  parameters:\n"
                           "    - {force: {load: 0, component: x}, mean: 0, stddev: 0.05}\n"
                           "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.05}\n"
                           "    - {force: {load: 0, component: z}, mean: 0, stddev: 0.05}\n"
                           "  observations:\n"
                           "    point_cloud: {files: \"pc*.txt\"}\n"
                           "    sigma: 1.0e-5\n"),
        "estimation.yaml", dir.string());
    results.push_back(runAssimilation(scene, (dir / std::to_string(threads)).string()));
  }
  for (size_t t = 1; t < results.size(); ++t)
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(results[t].parameters[i].mean, results[0].parameters[i].mean) << t + 1;
      EXPECT_EQ(results[t].parameters[i].stddev, results[0].parameters[i].stddev) << t + 1;
    }
  EXPECT_LE(std::abs(results[0].parameters[1].mean + 0.04), 0.004);  // N: the force's y
}

// The factorisations of each step in a run's timing.csv.
std::vector<double> factorizationsPerStep(const fs::path& run) {
  const CsvTable t = readCsvTable((run / "timing.csv").string());
  const int c = t.column("factorizations");
  EXPECT_GE(c, 0);
  std::vector<double> out;
  for (Eigen::Index r = 0; c >= 0 && r < t.rows.rows(); ++r) out.push_back(t.rows(r, c));
  return out;
}

// Static frames with tangent: mean, the force growing frame by frame. With tangent_background the
// mean tangents built on their own thread serve the mean (timing.csv counts them from step 2 on),
// the force is followed as closely as with the tangent rebuilt in the frame, and the estimates
// are the same on 1 and 2 threads. A linear law's tangent is exact everywhere: the mean's chord
// takes one step and the tangent is never rebuilt, whatever tangent_refresh_every says.
TEST(PointCloudForce, BackgroundTangentsServeTheMeanAndALinearLawKeepsItsOwn) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 6;
  const Vec3 force(0.015, -0.06, 0.0075);  // N, at the last frame: from half of it at the first
  for (int k = 1; k <= kSteps; ++k) {
    const Vec3 f = force * (0.5 + 0.1 * (k - 1));
    std::ostringstream load;
    load << '[' << f.x() << ", " << f.y() << ", " << f.z() << ']';
    writeTruthCloud(dir, kSteps, load.str());
    fs::rename(dir / "cloud.txt", dir / ("pc" + std::to_string(k) + ".txt"));
  }
  const auto run = [&](const std::string& name, const std::string& law, const std::string& tangent,
                       int threads) {
    std::string yaml = staticCylinder(
        "[0, 0, 0]", kSteps,
        "assimilation:\n  filter: roukf\n  tangent: mean\n  threads: " + std::to_string(threads) +
            "\n" + tangent +
            "  parameters:\n"
            "    - {force: {load: 0, component: x}, mean: 0, stddev: 0.05, "
            "random_walk: 0.01}\n"
            "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.05, "
            "random_walk: 0.01}\n"
            "    - {force: {load: 0, component: z}, mean: 0, stddev: 0.05, "
            "random_walk: 0.01}\n"
            "  observations:\n"
            "    point_cloud: {files: \"pc*.txt\"}\n"
            "    sigma: 1.0e-5\n");
    const std::string from = "model: neohookean";
    const size_t at = yaml.find(from);
    yaml = yaml.substr(0, at) + "model: " + law + yaml.substr(at + from.size());
    return runAssimilation(loadSceneFromString(yaml, "estimation.yaml", dir.string()),
                           (dir / name).string());
  };
  const auto forceOf = [](const AssimilationResult& r) {
    return Vec3(r.parameters[0].mean, r.parameters[1].mean, r.parameters[2].mean);
  };

  const std::string inBackground = "  tangent_refresh_every: 2\n  tangent_background: true\n";
  const AssimilationResult background = run("background", "neohookean", inBackground, 2);
  const AssimilationResult oneThread = run("background-1", "neohookean", inBackground, 1);
  const AssimilationResult inFrame = run("in-frame", "neohookean", "", 2);
  const std::vector<double> built = factorizationsPerStep(dir / "background");
  ASSERT_EQ(built.size(), static_cast<size_t>(kSteps));
  EXPECT_GE(std::accumulate(built.begin() + 1, built.end(), 0.0), 1.0);  // builds adopted
  const double error = (forceOf(background) - force).norm() / force.norm();
  const double inFrameError = (forceOf(inFrame) - force).norm() / force.norm();
  std::cout << "[ point-cloud force ] growing force, tangents in the background: " << 100 * error
            << " %, in the frame: " << 100 * inFrameError << " %\n";
  EXPECT_LE(error, 0.03);
  EXPECT_LE(std::abs(error - inFrameError), 0.005);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(oneThread.parameters[i].mean, background.parameters[i].mean) << i;
    EXPECT_EQ(oneThread.parameters[i].stddev, background.parameters[i].stddev) << i;
  }

  for (const std::string& tangent : {std::string("  tangent_refresh_every: 1\n"), inBackground}) {
    const std::string name = tangent == inBackground ? "linear-background" : "linear";
    const AssimilationResult linear = run(name, "linear", tangent, 2);
    const std::vector<double> linearBuilt = factorizationsPerStep(dir / name);
    ASSERT_EQ(linearBuilt.size(), static_cast<size_t>(kSteps));
    EXPECT_EQ(std::accumulate(linearBuilt.begin() + 1, linearBuilt.end(), 0.0), 0.0) << name;
    EXPECT_GT(forceOf(linear).norm(), 0.5 * force.norm()) << name;  // it did estimate
  }
}

// One frame, from a zero force: the closest points found on the rest surface are stale once the
// surface has moved several mm, so one analysis falls short; relinearisations find them again on
// the analysed surface (point_cloud.relinearizations) and reach the force in that one frame.
TEST(PointCloudForce, RelinearisationsRecoverTheForceInTheFirstFrame) {
  const fs::path dir = test::freshDir();
  const Vec3 force(0.04, -0.12, 0.02);  // N
  writeTruthCloud(dir, 1, "[0.04, -0.12, 0.02]");
  fs::copy_file(dir / "cloud.txt", dir / "pc1.txt");
  std::map<std::string, double> errors;
  for (const std::string filter : {"roukf", "ukf", "etkf"}) {
    for (const int passes : {0, 8}) {
      const std::string name = filter + "-" + std::to_string(passes);
      const Scene scene = loadSceneFromString(
          staticCylinder("[0, 0, 0]", 1,
                         "assimilation:\n  filter: " + filter +
                             (filter == "etkf" ? "\n  members: 12\n" : "\n") +
                             "  parameters:\n"
                             "    - {force: {load: 0, component: x}, mean: 0, stddev: 0.1}\n"
                             "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.1}\n"
                             "    - {force: {load: 0, component: z}, mean: 0, stddev: 0.1}\n"
                             "  observations:\n"
                             "    point_cloud: {files: \"pc*.txt\", relinearizations: " +
                             std::to_string(passes) +
                             "}\n"
                             "    sigma: 1.0e-4\n"),
          "estimation.yaml", dir.string());
      const AssimilationResult r = runAssimilation(scene, (dir / name).string());
      const Vec3 estimate(r.parameters[0].mean, r.parameters[1].mean, r.parameters[2].mean);
      errors[name] = (estimate - force).norm() / force.norm();
      std::cout << "[ first frame ] " << name << ": " << estimate.transpose()
                << " N: " << 100 * errors[name] << " %\n";
      // filter.csv's last column: the passes this frame took.
      std::ifstream csv(dir / name / "filter.csv");
      std::string header, row;
      ASSERT_TRUE(std::getline(csv, header) && std::getline(csv, row)) << name;
      ASSERT_EQ(header.substr(header.rfind(',') + 1), "cloud_relinearizations");
      const int taken = std::stoi(row.substr(row.rfind(',') + 1));
      if (passes == 0)
        EXPECT_EQ(taken, 0) << name;
      else
        EXPECT_TRUE(taken >= 2 && taken <= passes) << name << ": " << taken;
    }
    EXPECT_LE(errors[filter + "-8"], 0.02) << filter;
    EXPECT_GT(errors[filter + "-0"], 5 * errors[filter + "-8"]) << filter;
  }
}

// The first frame from a zero prior with `tangent: mean`: its sigma points are linearised about
// the rest shape, which a Neo-Hookean cylinder bent by a large force is far from, and one
// analysis (its closest points relinearised as often as need be) takes that linearisation's
// answer. Forecast again about the analysed force (reforecasts), the frame reaches the force
// that its own equilibrium explains; the counts are in timing.csv's last column.
TEST(PointCloudForce, ReforecastsTakeTheFirstFrameBeyondTheRestShapesLinearisation) {
  const fs::path dir = test::freshDir();
  const Vec3 force(0.06, -0.18, 0.03);  // N
  writeTruthCloud(dir, 1, "[0.06, -0.18, 0.03]");
  fs::copy_file(dir / "cloud.txt", dir / "pc1.txt");
  std::map<int, double> errors;
  for (const int reforecasts : {0, 4}) {
    const std::string name = "reforecasts-" + std::to_string(reforecasts);
    const Scene scene = loadSceneFromString(
        staticCylinder(
            "[0, 0, 0]", 1,
            "assimilation:\n  tangent: mean\n  reforecasts: " + std::to_string(reforecasts) +
                "\n"
                "  parameters:\n"
                "    - {force: {load: 0, component: x}, mean: 0, stddev: 0.1}\n"
                "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.1}\n"
                "    - {force: {load: 0, component: z}, mean: 0, stddev: 0.1}\n"
                "  observations:\n"
                "    point_cloud: {files: \"pc*.txt\", relinearizations: 8}\n"
                "    sigma: 1.0e-4\n"),
        "estimation.yaml", dir.string());
    const AssimilationResult r = runAssimilation(scene, (dir / name).string());
    const Vec3 estimate(r.parameters[0].mean, r.parameters[1].mean, r.parameters[2].mean);
    errors[reforecasts] = (estimate - force).norm() / force.norm();
    std::cout << "[ first frame ] " << name << ": " << estimate.transpose()
              << " N: " << 100 * errors[reforecasts] << " %\n";
    std::ifstream csv(dir / name / "timing.csv");
    std::string header, row;
    ASSERT_TRUE(std::getline(csv, header) && std::getline(csv, row)) << name;
    ASSERT_EQ(header.substr(header.rfind(',') + 1), "reforecasts");
    const int taken = std::stoi(row.substr(row.rfind(',') + 1));
    if (reforecasts == 0)
      EXPECT_EQ(taken, 0);
    else
      EXPECT_TRUE(taken >= 1 && taken <= reforecasts) << taken;
  }
  EXPECT_LE(errors[4], 0.005);
  EXPECT_GT(errors[0], 0.02);
}

// A slab fixed at its base, a tool pressing on a 3 x 3 cm zone of its top (z = 0.02 m).
std::string staticSlab(int steps, const std::string& extra) {
  return "mesh: {generator: box, size: [0.08, 0.08, 0.02], cells: [12, 12, 3]}\n"
         "material: {model: neohookean, young_modulus: 5000, poisson_ratio: 0.45}\n"
         "integrator: {type: static, tolerance: 1.0e-10}\n"
         "time: {dt: 1, steps: " +
         std::to_string(steps) +
         "}\n"
         "fixed:\n"
         "  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
         "loads:\n"
         "  - region: {surface_patch: {box: {min: [0.025, 0.025, 0.019], max: [0.055, 0.055, "
         "0.021]}, direction: [0, 0, 1], max_angle_deg: 30}}\n"
         "    total_force: [0, 0, 0]\n"
         "output: {pvd: false}\n" +
         extra;
}

// The tool presses off the zone's centre on a narrower footprint than the even split, seen from
// above: estimating the footprint (tilts and concentration) with the force recovers both; the
// even split cannot place the force and misjudges it.
TEST(PointCloudForce, AnOffCentreFootprintIsRecoveredWithTheForce) {
  const fs::path dir = test::freshDir();
  constexpr int kFrames = 20;
  const Vec3 force(0.1, -0.05, -0.8);    // N
  const Vec3 footprint(1.2, -0.6, 1.5);  // tilt u, tilt v, concentration
  {
    Scene truth = loadSceneFromString(staticSlab(1, ""), "truth.yaml", dir.string());
    for (int c = 0; c < 3; ++c) {
      applyParameter(LoadForceTarget{0, c}, force(c), truth.model);
      applyParameter(LoadFootprintTarget{0, c}, footprint(c), truth.model);
    }
    StaticSolver solver(truth.model, makeLinearSolver("cholmod"), truth.statics);
    Eigen::VectorXd x = truth.model.restPositions();
    solver.solve(truth.model, 1.0, x);
    ASSERT_GT((x - truth.model.restPositions()).cwiseAbs().maxCoeff(), 2e-3);
    // The camera above sees the top face: its deformed nodes.
    std::ofstream cloud(dir / "cloud.txt");
    for (int n = 0; n < truth.model.mesh->numNodes(); ++n)
      if (truth.model.mesh->V(n, 2) > 0.0199)
        cloud << x(3 * n) << ' ' << x(3 * n + 1) << ' ' << x(3 * n + 2) << '\n';
  }
  for (int k = 1; k <= kFrames; ++k)
    fs::copy_file(dir / "cloud.txt", dir / ("pc" + std::to_string(k) + ".txt"));
  const std::string forceParameters =
      "    - {force: {load: 0, component: x}, mean: 0, stddev: 0.5}\n"
      "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.5}\n"
      "    - {force: {load: 0, component: z}, mean: 0, stddev: 0.5}\n";
  const std::string footprintParameters =
      "    - {force: {load: 0, footprint: tilt_u}, mean: 0, stddev: 1}\n"
      "    - {force: {load: 0, footprint: tilt_v}, mean: 0, stddev: 1}\n"
      "    - {force: {load: 0, footprint: concentration}, mean: 0, stddev: 1}\n";
  double evenError = 0.0, evenMedian = 0.0;
  // The last frame's median distance of the cloud to the analysed surface (filter.csv), m.
  auto lastMedian = [&](const std::string& name) {
    std::ifstream csv(dir / name / "filter.csv");
    std::string line, last;
    while (std::getline(csv, line)) last = line;
    std::stringstream row(last);
    std::string field;
    for (int c = 0; c < 8; ++c) std::getline(row, field, ',');  // cloud_median_distance_m
    return std::stod(field);
  };
  for (const bool estimateFootprint : {false, true}) {
    const std::string name = estimateFootprint ? "footprint" : "even";
    const Scene scene = loadSceneFromString(
        staticSlab(kFrames, "assimilation:\n  parameters:\n" + forceParameters +
                                (estimateFootprint ? footprintParameters : "") +
                                "  observations:\n"
                                "    point_cloud: {files: \"pc*.txt\", relinearizations: 8}\n"
                                "    sigma: 1.0e-5\n"),
        "estimation.yaml", dir.string());
    const AssimilationResult r = runAssimilation(scene, (dir / name).string());
    const Vec3 estimate(r.parameters[0].mean, r.parameters[1].mean, r.parameters[2].mean);
    const double error = (estimate - force).norm() / force.norm();
    const double median = lastMedian(name);
    std::cout << "[ footprint ] " << name << ": " << estimate.transpose() << " N, " << 100 * error
              << " %, cloud median distance " << 1e6 * median << " um";
    if (estimateFootprint) {
      ASSERT_EQ(r.parameters.size(), 6u);
      const Vec3 f(r.parameters[3].mean, r.parameters[4].mean, r.parameters[5].mean);
      std::cout << "; footprint " << f.transpose();
      EXPECT_EQ(r.parameters[3].name, "tilt_u_0");
      EXPECT_EQ(r.parameters[5].name, "concentration_0");
      EXPECT_LE(error, 0.02);
      EXPECT_LT((f - footprint).cwiseAbs().maxCoeff(), 0.15);
      EXPECT_LT(error, evenError);
      // The even split cannot take the surface's shape: its fit stays 3x farther from the cloud.
      EXPECT_LT(3 * median, evenMedian);
    } else {
      evenError = error;
      evenMedian = median;
    }
    std::cout << "\n";
  }
}

// A frame in millimetres for a mesh in metres (tracking's unit check) is left out with one
// notice; the run goes on with the other frames.
// The cylinder with a zero force, its y component estimated from dir's pc*.txt frames;
// `cloudExtra` goes into the point_cloud map (", keep_fraction: 0.4"), `sigma` in m.
// `observationsExtra`: more lines of the observations map.
Scene forceFromClouds(const fs::path& dir, int steps, const std::string& cloudExtra,
                      const std::string& sigma, const std::string& observationsExtra = "") {
  return loadSceneFromString(
      staticCylinder("[0, 0, 0]", steps,
                     "assimilation:\n"
                     "  parameters:\n"
                     "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.05}\n"
                     "  observations:\n"
                     "    point_cloud: {files: \"pc*.txt\"" +
                         cloudExtra + "}\n    sigma: " + sigma + "\n" + observationsExtra),
      "estimation.yaml", dir.string());
}

TEST(PointCloudForce, AFrameInMillimetresIsLeftOutWithANotice) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 3;
  writeTruthCloud(dir, kSteps);
  fs::copy_file(dir / "cloud.txt", dir / "pc1.txt");
  fs::copy_file(dir / "cloud.txt", dir / "pc3.txt");
  {
    std::ifstream in(dir / "cloud.txt");
    std::ofstream mm(dir / "pc2.txt");
    for (double x, y, z; in >> x >> y >> z;)
      mm << 1000 * x << ' ' << 1000 * y << ' ' << 1000 * z << '\n';
  }
  const AssimilationResult r =
      runAssimilation(forceFromClouds(dir, kSteps, "", "1.0e-5"), (dir / "est").string());
  EXPECT_EQ(r.observedSteps, 2);
  ASSERT_EQ(r.notices.size(), 1u);
  EXPECT_EQ(r.notices[0].rfind("pc2.txt: ", 0), 0u) << r.notices[0];
  EXPECT_NE(r.notices[0].find("; step 2 is a prediction only"), std::string::npos) << r.notices[0];
  std::ifstream notices(dir / "est" / "notices.txt");
  std::string line;
  ASSERT_TRUE(std::getline(notices, line));
  EXPECT_EQ(line, r.notices[0]);
}

// A table under the cylinder, with a few more points than the organ's part of the view: the median
// distance lies on the table, the robust cutoff keeps it, and the run says so once (the first
// frame). Counting only the closest 40 % of the points (keep_fraction) leaves the table out, the
// fit is close and nothing is said.
TEST(PointCloudForce, AFrameTheModelDoesNotFitIsNamedOnce) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 2;
  writeTruthCloud(dir, kSteps);
  std::vector<Vec3> organ;
  {
    std::ifstream in(dir / "cloud.txt");
    for (double x, y, z; in >> x >> y >> z;) organ.emplace_back(x, y, z);
  }
  const int tableSide = static_cast<int>(std::ceil(std::sqrt(1.3 * organ.size())));
  for (int frame = 1; frame <= kSteps; ++frame) {
    std::ofstream out(dir / ("pc" + std::to_string(frame) + ".txt"));
    for (const Vec3& p : organ) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (int i = 0; i < tableSide; ++i)  // 3.5 cm under the cylinder's axis, 2 cm under its side
      for (int j = 0; j < tableSide; ++j)
        out << -0.03 + 0.06 * i / tableSide << " -0.035 " << 0.18 * (j + 0.5) / tableSide << '\n';
  }
  const auto notices = [&](const std::string& extra) {
    return runAssimilation(forceFromClouds(dir, kSteps, extra, "1.0e-4"),
                           (dir / ("est" + extra.substr(0, 4))).string())
        .notices;
  };
  const std::vector<std::string> kept = notices("");
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].rfind("pc1.txt: step 1 (t = 1 s): its points lie a median ", 0), 0u) << kept[0];
  EXPECT_NE(kept[0].find("set point_cloud.keep_fraction"), std::string::npos) << kept[0];
  EXPECT_NE(kept[0].find("need observations.frame_transform"), std::string::npos) << kept[0];
  EXPECT_TRUE(notices(", keep_fraction: 0.4").empty());
}

// The clouds as a camera sees them, 20 degrees turned and 10 cm away, with the camera -> model
// motion as `bcassim register` writes it (observations.frame_transform): the same estimate as
// from the clouds in the model's frame, to round-off.
TEST(PointCloudForce, CloudsInACameraFrameGiveTheSameEstimateThroughFrameTransform) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 2;
  writeTruthCloud(dir, kSteps);
  Eigen::MatrixX3d model;
  {
    std::vector<double> v;
    std::ifstream in(dir / "cloud.txt");
    for (double c; in >> c;) v.push_back(c);
    model = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        v.data(), static_cast<Eigen::Index>(v.size() / 3), 3);
  }
  RigidTransform cameraToModel;
  cameraToModel.rotation =
      Eigen::AngleAxisd(20 * M_PI / 180, Vec3(0.2, -1, 0.4).normalized()).toRotationMatrix();
  cameraToModel.translation = Vec3(0.06, 0.02, -0.08);
  const Eigen::MatrixX3d camera = cameraToModel.inverse().apply(model);
  fs::create_directories(dir / "camera");
  std::ofstream matrix(dir / "camera" / "transform.csv");
  for (int r = 0; r < 3; ++r)
    matrix << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}\n", cameraToModel.rotation(r, 0),
                          cameraToModel.rotation(r, 1), cameraToModel.rotation(r, 2),
                          cameraToModel.translation(r));
  matrix << "0,0,0,1\n";
  matrix.close();
  for (int frame = 1; frame <= kSteps; ++frame) {
    const std::string name = "pc" + std::to_string(frame) + ".txt";
    fs::copy_file(dir / "cloud.txt", dir / name);
    std::ofstream out(dir / "camera" / name);
    for (Eigen::Index i = 0; i < camera.rows(); ++i)
      out << fmt::format("{:.17g} {:.17g} {:.17g}\n", camera(i, 0), camera(i, 1), camera(i, 2));
  }
  const AssimilationResult inModel =
      runAssimilation(forceFromClouds(dir, kSteps, "", "1.0e-5"), (dir / "model").string());
  const AssimilationResult inCamera = runAssimilation(
      forceFromClouds(dir / "camera", kSteps, "", "1.0e-5", "    frame_transform: transform.csv\n"),
      (dir / "camera-run").string());
  ASSERT_EQ(inCamera.parameters.size(), 1u);
  EXPECT_LT(inModel.parameters[0].mean, -0.01);  // N: the truth's -0.04 seen
  EXPECT_NEAR(inCamera.parameters[0].mean, inModel.parameters[0].mean,
              1e-9 * std::abs(inModel.parameters[0].mean));
  EXPECT_TRUE(inCamera.notices.empty());
}

// A camera registration a few degrees and millimetres off: the force estimated alone bends the
// model towards the misplaced points; with the pose's coordinates estimated beside it
// (parameters `pose: rx ...`), the force comes back within 2 % and the pose within 10 % of the
// error put in. (The cylinder's own symmetries, a turn about its axis and a slide along it, are
// left out: the surface cannot tell them.)
TEST(PointCloudForce, APoseErrorOfTheObservationsIsEstimatedWithTheForce) {
  const fs::path dir = test::freshDir();
  constexpr int kSteps = 3;
  const double force = -0.04;  // N, y
  writeTruthCloud(dir, kSteps, "[0, -0.04, 0]");
  const Scene rest =
      loadSceneFromString(staticCylinder("[0, 0, 0]", kSteps, ""), "rest.yaml", dir.string());
  const Vec3 centre = rest.model.mesh->V.colwise().mean().transpose();
  const Vec3 rotation(0.03, -0.02, 0);  // rad
  const Vec3 shift(0.002, -0.003, 0);   // m
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(rotation.norm(), rotation.normalized()).toRotationMatrix();
  {
    std::ifstream in(dir / "cloud.txt");
    std::string moved;
    for (double x, y, z; in >> x >> y >> z;) {
      const Vec3 p = R * (Vec3(x, y, z) - centre) + centre + shift;
      moved += fmt::format("{:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
    }
    for (int k = 1; k <= kSteps; ++k)
      std::ofstream(dir / ("pc" + std::to_string(k) + ".txt")) << moved;
  }
  const std::string forceParameter =
      "    - {force: {load: 0, component: y}, mean: 0, stddev: 0.05}\n";
  const std::string poseParameters =
      "    - {pose: rx, mean: 0, stddev: 0.05}\n"
      "    - {pose: ry, mean: 0, stddev: 0.05}\n"
      "    - {pose: tx, mean: 0, stddev: 0.005}\n"
      "    - {pose: ty, mean: 0, stddev: 0.005}\n";
  auto run = [&](const std::string& name, const std::string& parameters) {
    return runAssimilation(
        loadSceneFromString(
            staticCylinder("[0, 0, 0]", kSteps,
                           "assimilation:\n  parameters:\n" + parameters +
                               "  observations:\n"
                               "    point_cloud: {files: \"pc*.txt\", relinearizations: 8}\n"
                               "    sigma: 1.0e-5\n"),
            "estimation.yaml", dir.string()),
        (dir / name).string());
  };
  const AssimilationResult alone = run("force", forceParameter);
  const AssimilationResult withPose = run("pose", forceParameter + poseParameters);
  const double aloneError = std::abs(alone.parameters[0].mean - force) / std::abs(force);
  const double poseError = std::abs(withPose.parameters[0].mean - force) / std::abs(force);
  ASSERT_EQ(withPose.parameters.size(), 5u);
  const Eigen::Vector4d truth(rotation.x(), rotation.y(), shift.x(), shift.y());
  Eigen::Vector4d estimate;
  for (int i = 0; i < 4; ++i) estimate(i) = withPose.parameters[static_cast<size_t>(i) + 1].mean;
  std::cout << "[ pose ] force alone " << alone.parameters[0].mean << " N (" << 100 * aloneError
            << " %), with the pose " << withPose.parameters[0].mean << " N (" << 100 * poseError
            << " %); pose " << estimate.transpose() << " (truth " << truth.transpose() << ")\n";
  EXPECT_LE(poseError, 0.02);
  EXPECT_GT(aloneError, 5 * poseError);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(estimate(i), truth(i), 0.1 * std::abs(truth(i))) << i;
}

}  // namespace
}  // namespace bcassim
