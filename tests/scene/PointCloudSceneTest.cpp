// The scene keys of issue 14 (observations.point_cloud, force parameters with a random walk,
// static assimilation, loads given frame by frame, control points from tracks): their errors name
// line and key, and bad frames become one notice each while the run keeps what it can use.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/scene/ModelParameter.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

using test::writeText;

// 12 points on the top face (z = 0.02) of the box below, as "x y z" lines.
std::string twelvePoints() {
  std::string text;
  for (int i = 0; i < 12; ++i) text += std::to_string(0.005 + 0.007 * i) + " 0.01 0.02\n";
  return text;
}

const char* kStaticBox =
    "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [5, 1, 1]}\n"
    "integrator: {type: static}\n"
    "time: {dt: 1, steps: 4}\n"
    "fixed: [{region: {half_space: {point: [0.001, 0, 0], normal: [-1, 0, 0]}}}]\n";

const char* kLoad = "loads: [{region: {nodes: [20, 21]}, total_force: [0, 0, 0]}]\n";

std::string assimilation(const std::string& parameters, const std::string& observations) {
  return "assimilation:\n  parameters:\n" + parameters + "  observations:\n" + observations;
}

const char* kForceX = "    - {force: {load: 0, component: x}, mean: 0, stddev: 1}\n";
const char* kCloud = "    point_cloud: {files: \"pc*.txt\"}\n";

std::string errorOf(const std::string& yaml, const fs::path& dir) {
  try {
    loadSceneFromString(yaml, "scene.yaml", dir.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

fs::path cloudDir() {
  const fs::path dir = test::freshDir();
  for (int k = 1; k <= 4; ++k) writeText(dir / ("pc" + std::to_string(k) + ".txt"), twelvePoints());
  return dir;
}

// tangent_precision chooses the dynamic steps' solves; static frames' chord steps are in float
// whatever it says, so it is refused there rather than ignored.
TEST(PointCloudScene, TangentPrecisionIsRefusedWithStaticFrames) {
  const fs::path dir = cloudDir();
  const std::string yaml = std::string(kStaticBox) + kLoad + assimilation(kForceX, kCloud) +
                           "  tangent: mean\n  tangent_precision: double\n";
  const std::string error = errorOf(yaml, dir);
  EXPECT_NE(error.find("assimilation.tangent_precision: only for dynamic frames (static ones "
                       "solve their chord steps in float already)"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

TEST(PointCloudScene, ForceParametersAndStaticAssimilationAreRead) {
  const fs::path dir = cloudDir();
  const Scene s = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          assimilation("    - {force: {load: 0, component: y}, mean: 0.5, stddev: 1, "
                       "random_walk: 0.2}\n",
                       kCloud),
      "scene.yaml", dir.string());
  ASSERT_TRUE(s.assimilation);
  const EstimatedParameter& p = s.assimilation->parameters.at(0);
  EXPECT_EQ(p.name, "Fy_0");
  EXPECT_DOUBLE_EQ(p.randomWalkPerStep, 0.2);  // N per sqrt(s), dt = 1 s
  EXPECT_FALSE(s.assimilation->carryPositions);
  EXPECT_FALSE(s.assimilation->carryVelocities);
  ASSERT_TRUE(s.assimilation->observations.pointCloud);
  const PointCloudSettings& pc = *s.assimilation->observations.pointCloud;
  EXPECT_EQ(pc.frames.size(), 5u);
  for (int k = 1; k <= 4; ++k) EXPECT_EQ(pc.frames[static_cast<size_t>(k)].rows(), 12);
  EXPECT_EQ(pc.relinearizations, 0);  // one analysis per frame unless asked
  EXPECT_TRUE(s.assimilation->notices.empty());
  const Scene passes = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", relinearizations: 4}\n"),
      "scene.yaml", dir.string());
  EXPECT_EQ(passes.assimilation->observations.pointCloud->relinearizations, 4);
  // The footprint's coefficients: dimensionless, named after the load.
  const Scene footprint = loadSceneFromString(
      std::string(kStaticBox) +
          "loads: [{region: {nodes: [20, 21, 22, 23]}, total_force: [0, 0, 0]}]\n" +
          assimilation("    - {force: {load: 0, footprint: tilt_u}, mean: 0, stddev: 1}\n"
                       "    - {force: {load: 0, footprint: concentration}, mean: 0.5, stddev: 1}\n",
                       kCloud),
      "scene.yaml", dir.string());
  const auto& fp = footprint.assimilation->parameters;
  ASSERT_EQ(fp.size(), 2u);
  EXPECT_EQ(fp[0].name, "tilt_u_0");
  EXPECT_EQ(fp[1].name, "concentration_0");
}

// The observations' pose: rotations in rad, translations in m, named pose_<coordinate>; each
// coordinate once; it leaves the mechanics as they are.
TEST(PointCloudScene, PoseParametersAreReadInRadiansAndMetres) {
  const fs::path dir = cloudDir();
  Scene s = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          assimilation(std::string(kForceX) + "    - {pose: rz, mean: 0, stddev: 0.05}\n"
                                              "    - {pose: ty, mean: 0.001, stddev: 0.005}\n",
                       kCloud),
      "scene.yaml", dir.string());
  const auto& p = s.assimilation->parameters;
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[1].name, "pose_rz");
  EXPECT_EQ(std::get<ObservationPoseTarget>(p[1].target).component, 2);
  EXPECT_EQ(p[2].name, "pose_ty");
  EXPECT_EQ(std::get<ObservationPoseTarget>(p[2].target).component, 4);
  const Eigen::VectorXd before = s.model.restPositions();
  applyParameter(p[1].target, 0.3, s.model);
  EXPECT_EQ(readParameter(p[1].target, s.model), 0.0);
  EXPECT_EQ(s.model.restPositions(), before);
  EXPECT_EQ(errorOf(std::string(kStaticBox) + kLoad +
                        assimilation("    - {pose: tx, mean: 0, stddev: 1}\n"
                                     "    - {pose: tx, name: again, mean: 0, stddev: 1}\n",
                                     kCloud),
                    dir),
            "scene.yaml:9: assimilation.parameters[1].pose: pose_tx is estimated twice; expected "
            "each pose coordinate once");
  EXPECT_EQ(errorOf(std::string(kStaticBox) + kLoad +
                        assimilation("    - {pose: x, mean: 0, stddev: 1}\n", kCloud),
                    dir),
            "scene.yaml:8: assimilation.parameters[0].pose: expected one of rx, ry, rz, tx, ty, "
            "tz, got 'x'");
  EXPECT_EQ(
      errorOf(std::string(kStaticBox) + kLoad + assimilation("    - {pose: rx, mean: 0}\n", kCloud),
              dir),
      "scene.yaml:8: assimilation.parameters[0].stddev: missing (initial standard "
      "deviation, rad)");
  EXPECT_EQ(
      errorOf(std::string(kStaticBox) + kLoad +
                  assimilation("    - {pose: rx, force: {load: 0, component: x}, mean: 0, "
                               "stddev: 1}\n",
                               kCloud),
              dir),
      "scene.yaml:8: assimilation.parameters[0]: expected exactly one of young_modulus, spring, "
      "force, pose (what it sets)");
}

// A footprint coefficient reshapes how the load's total force is shared, never the total: set
// before or after the force components, the nodal forces sum to the total.
TEST(PointCloudScene, AFootprintKeepsTheLoadsTotalForce) {
  Scene s = loadSceneFromString(
      std::string(kStaticBox) +
          "loads: [{region: {nodes: [20, 21, 22, 23]}, total_force: [1, 2, 3]}]\n",
      "scene.yaml", test::freshDir().string());
  auto nodalSum = [&] {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * s.model.mesh->numNodes());
    s.model.loads[0].addTo(1.0, f);
    return Vec3(f.reshaped(3, f.size() / 3).rowwise().sum());
  };
  EXPECT_LT((nodalSum() - Vec3(1, 2, 3)).norm(), 1e-12);
  applyParameter(LoadFootprintTarget{0, 0}, 0.8, s.model);
  applyParameter(LoadFootprintTarget{0, 2}, 1.5, s.model);
  EXPECT_LT((nodalSum() - Vec3(1, 2, 3)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(readParameter(LoadFootprintTarget{0, 0}, s.model), 0.8);
  EXPECT_DOUBLE_EQ(readParameter(LoadFootprintTarget{0, 1}, s.model), 0.0);
  applyParameter(LoadForceTarget{0, 2}, 5.0, s.model);
  EXPECT_LT((nodalSum() - Vec3(1, 2, 5)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(readParameter(LoadForceTarget{0, 2}, s.model), 5.0);
  const std::vector<double>& w = s.model.loads[0].weights;
  ASSERT_EQ(w.size(), 4u);
  EXPECT_GT(*std::max_element(w.begin(), w.end()), 0.26);  // no longer the even split
}

TEST(PointCloudScene, ErrorsNameLineAndKey) {
  const fs::path dir = cloudDir();
  const std::string b = std::string(kStaticBox);
  EXPECT_EQ(errorOf(b + assimilation(kForceX, kCloud), dir),
            "scene.yaml:7: assimilation.parameters[0].force.load: the scene has no loads (the "
            "zone the force acts on)");
  EXPECT_EQ(
      errorOf(b + kLoad + assimilation("    - {force: {load: 0}, mean: 0, stddev: 1}\n", kCloud),
              dir),
      "scene.yaml:8: assimilation.parameters[0].force.component: missing (x, y or z)");
  EXPECT_EQ(errorOf(b + kLoad +
                        assimilation("    - {force: {load: 0, component: x}, mean: 0, stddev: 1, "
                                     "random_walk: 1, random_walk_per_step: 1}\n",
                                     kCloud),
                    dir),
            "scene.yaml:8: assimilation.parameters[0].random_walk_per_step: expected either "
            "random_walk or random_walk_per_step, not both");
  EXPECT_EQ(
      errorOf(b + kLoad + assimilation(kForceX, "    point_cloud: {residual: normal}\n"), dir),
      "scene.yaml:10: assimilation.observations.point_cloud.files: missing (a folder or "
      "pattern of frame files, or a csv)");
  EXPECT_EQ(
      errorOf(b + kLoad + assimilation(kForceX, std::string(kCloud) + "    tracks: t.csv\n"), dir),
      "scene.yaml:10: assimilation.observations.tracks: expected either tracks or "
      "point_cloud, not both");
  EXPECT_EQ(
      errorOf(b + kLoad + "assimilation:\n  state: {positions: true}\n  parameters:\n" + kForceX +
                  "  observations:\n" + kCloud,
              dir),
      "scene.yaml:7: assimilation.state.positions: true does not go with integrator.type static "
      "(every frame is an equilibrium of the parameters: the filter estimates parameters only)");
  EXPECT_EQ(
      errorOf(b + kLoad +
                  assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", min_points: 13}\n"),
              dir),
      "scene.yaml:10: assimilation.observations.point_cloud: no frame with at least min_points "
      "(13) points within time.steps (4)");
  EXPECT_EQ(
      errorOf(b + kLoad +
                  assimilation(kForceX,
                               "    point_cloud: {files: \"pc*.txt\", relinearizations: -1}\n"),
              dir),
      "scene.yaml:10: assimilation.observations.point_cloud.relinearizations: must be >= 0, "
      "got -1");
  EXPECT_EQ(
      errorOf(b + kLoad +
                  assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", voxel_size: -1}\n"),
              dir),
      "scene.yaml:10: assimilation.observations.point_cloud.voxel_size: must be >= 0 metres, got "
      "-1");
  EXPECT_EQ(errorOf(b + kLoad +
                        assimilation(kForceX,
                                     "    point_cloud: {files: \"pc*.txt\", voxel_size: 1e-9}\n"),
                    dir),
            "scene.yaml:10: assimilation.observations.point_cloud.voxel_size: 1e-09 m; expected 0 "
            "(none) or an edge from 1e-6 to 1 m");
  EXPECT_EQ(errorOf(b + kLoad +
                        assimilation(kForceX,
                                     "    point_cloud: {files: \"pc*.txt\", keep_fraction: 1.5}\n"),
                    dir),
            "scene.yaml:10: assimilation.observations.point_cloud.keep_fraction: 1.5; expected a "
            "fraction in (0, 1] of each frame's points");
  EXPECT_EQ(
      errorOf(
          b + kLoad +
              assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", max_distance: 0.002}\n"),
          dir),
      "scene.yaml:10: assimilation.observations.point_cloud.max_distance: 0.002 m is below "
      "min_distance (0.005 m); expected at least that");
  EXPECT_EQ(
      errorOf(b + kLoad +
                  assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", max_points: 5}\n"),
              dir),
      "scene.yaml:10: assimilation.observations.point_cloud.max_points: 5; expected at least 8 "
      "(and at least min_points, 10)");
  EXPECT_EQ(errorOf(b + kLoad +
                        assimilation("    - {force: {load: 0, footprint: tilt_u}, mean: 0, "
                                     "stddev: 1}\n",
                                     kCloud),
                    dir),
            "scene.yaml:8: assimilation.parameters[0].force.footprint: loads[0] has 2 nodes; a "
            "footprint needs at least 3");
  EXPECT_EQ(errorOf(b + "loads: [{region: {nodes: [20, 21, 22]}, total_force: [0, 0, 0]}]\n" +
                        assimilation("    - {force: {load: 0, footprint: tilt_v, component: x}, "
                                     "mean: 0, stddev: 1}\n",
                                     kCloud),
                    dir),
            "scene.yaml:8: assimilation.parameters[0].force.footprint: expected either component "
            "or footprint, not both");
  EXPECT_EQ(errorOf(b + "loads: [{region: {nodes: [20, 21, 22]}, total_force: [0, 0, 0]}]\n" +
                        assimilation("    - {force: {load: 0, footprint: tilt}, mean: 0, "
                                     "stddev: 1}\n",
                                     kCloud),
                    dir),
            "scene.yaml:8: assimilation.parameters[0].force.footprint: expected one of tilt_u, "
            "tilt_v, concentration, got 'tilt'");
  EXPECT_EQ(errorOf(b + "loads: [{region: {nodes: [20]}, total_force: [0, 0, 1], "
                        "total_force_frames: f.txt}]\n",
                    dir),
            "scene.yaml:5: loads[0].total_force: expected either total_force_frames or "
            "total_force, not both");
}

// A dense frame (an RGB-D sensor's) is averaged on a voxel grid down to max_points, with one
// notice; a sparse one is kept as read unless voxel_size asks for a grid.
TEST(PointCloudScene, DenseFramesAreThinnedToMaxPoints) {
  const fs::path dir = test::freshDir();
  std::string dense;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 20; ++j)
      dense += std::to_string(0.0005 + 0.0016 * i) + " " + std::to_string(0.0005 + 0.001 * j) +
               " 0.02\n";
  writeText(dir / "pc1.txt", dense);
  writeText(dir / "pc2.txt", twelvePoints());
  const Scene s = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", max_points: 100}\n"),
      "scene.yaml", dir.string());
  const PointCloudSettings& pc = *s.assimilation->observations.pointCloud;
  EXPECT_EQ(pc.maxPoints, 100);
  EXPECT_LE(pc.frames[1].rows(), 100);
  EXPECT_GE(pc.frames[1].rows(), 30);
  EXPECT_EQ(pc.frames[2].rows(), 12);
  ASSERT_EQ(s.assimilation->notices.size(), 1u);
  EXPECT_EQ(s.assimilation->notices[0].rfind("point_cloud: 1 frame averaged on voxel grids of ", 0),
            0u)
      << s.assimilation->notices[0];
  EXPECT_NE(s.assimilation->notices[0].find("(voxel_size 0 m, max_points 100): "),
            std::string::npos)
      << s.assimilation->notices[0];
  const Scene grid = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          assimilation(kForceX, "    point_cloud: {files: \"pc*.txt\", voxel_size: 0.01}\n"),
      "scene.yaml", dir.string());
  // 1 cm cubes: the dense frame's 9.5 x 2 cm strip in 10 x 2 of them.
  EXPECT_EQ(grid.assimilation->observations.pointCloud->frames[1].rows(), 20);
}

// Observations in a camera's frame: observations.frame_transform (as `bcassim register` writes
// it, camera -> model) moves every cloud point and tracked marker into the model's frame as they
// are read; markers not seen stay not seen.
TEST(PointCloudScene, FrameTransformMovesTheObservationsIntoTheModelsFrame) {
  const fs::path dir = test::freshDir();
  RigidTransform cameraToModel;
  cameraToModel.rotation = Eigen::AngleAxisd(0.6, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  cameraToModel.translation = Vec3(0.1, -0.05, 0.2);
  std::string matrix;
  for (int r = 0; r < 4; ++r) {
    const Eigen::RowVector4d row =
        r < 3 ? Eigen::RowVector4d(cameraToModel.rotation(r, 0), cameraToModel.rotation(r, 1),
                                   cameraToModel.rotation(r, 2), cameraToModel.translation(r))
              : Eigen::RowVector4d(0, 0, 0, 1);
    matrix += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}\n", row(0), row(1), row(2), row(3));
  }
  writeText(dir / "T.csv", matrix);
  Eigen::MatrixX3d model(12, 3);
  for (int i = 0; i < 12; ++i) model.row(i) = Vec3(0.005 + 0.007 * i, 0.01, 0.02);
  const Eigen::MatrixX3d camera = cameraToModel.inverse().apply(model);
  std::string frame;
  for (Eigen::Index i = 0; i < camera.rows(); ++i)
    frame += fmt::format("{:.17g} {:.17g} {:.17g}\n", camera(i, 0), camera(i, 1), camera(i, 2));
  for (int k = 1; k <= 4; ++k) writeText(dir / ("pc" + std::to_string(k) + ".txt"), frame);
  const Scene s = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          assimilation(kForceX, std::string(kCloud) + "    frame_transform: T.csv\n"),
      "scene.yaml", dir.string());
  const PointCloudSettings& pc = *s.assimilation->observations.pointCloud;
  for (int k = 1; k <= 4; ++k) EXPECT_LT((pc.frames[k] - model).cwiseAbs().maxCoeff(), 1e-15);

  // Two markers; the second is not seen at t = 1 s.
  writeText(dir / "tracks.csv",
            fmt::format("time,marker,x,y,z\n1,0,{:.17g},{:.17g},{:.17g}\n2,0,{:.17g},{:.17g},"
                        "{:.17g}\n2,1,{:.17g},{:.17g},{:.17g}\n",
                        camera(0, 0), camera(0, 1), camera(0, 2), camera(1, 0), camera(1, 1),
                        camera(1, 2), camera(2, 0), camera(2, 1), camera(2, 2)));
  const Scene t = loadSceneFromString(
      std::string(kStaticBox) + kLoad +
          "markers: [{points: [[0.005, 0.01, 0.02], [0.012, 0.01, 0.02]]}]\n" +
          assimilation(kForceX, "    tracks: tracks.csv\n    frame_transform: T.csv\n"),
      "scene.yaml", dir.string());
  const TrackFrames& tracks = t.assimilation->observations.tracks;
  EXPECT_LT((tracks.frames[1].row(0) - model.row(0)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_TRUE(tracks.frames[1].row(1).hasNaN());
  EXPECT_LT((tracks.frames[2].topRows(2) - model.middleRows(1, 2)).cwiseAbs().maxCoeff(), 1e-15);
  ASSERT_TRUE(t.assimilation->observations.frameTransform);  // for streamed markers (serve)

  // What is not a rigid motion in metres is refused, naming the scene's key and the file.
  writeText(dir / "mm.txt", "0.001 0 0 0\n0 0.001 0 0\n0 0 0.001 0\n0 0 0 1\n");
  EXPECT_EQ(
      errorOf(std::string(kStaticBox) + kLoad +
                  assimilation(kForceX, std::string(kCloud) + "    frame_transform: mm.txt\n"),
              dir),
      "scene.yaml:11: assimilation.observations.frame_transform: " + (dir / "mm.txt").string() +
          ": the upper-left 3 x 3 scales lengths by 0.001, not a rotation (a change of "
          "units?); expected a rigid transform in metres");
  EXPECT_EQ(
      errorOf(std::string(kStaticBox) + kLoad +
                  assimilation(kForceX, std::string(kCloud) + "    frame_transform: none.csv\n"),
              dir)
          .rfind("scene.yaml:11: assimilation.observations.frame_transform: ", 0),
      0u);
}

TEST(PointCloudScene, BadFramesAreNoticesAndTheOthersAreKept) {
  const fs::path dir = test::freshDir();
  writeText(dir / "pc1.txt", twelvePoints());
  writeText(dir / "pc2.txt", "");
  writeText(dir / "pc3.txt", twelvePoints() + "nan 0.01 0.02\n0.01 inf 0.02\n");
  writeText(dir / "pc4.txt", "0.01 0.01 0.02\n0.02 0.01 0.02\n0.03 0.01 0.02\n");
  const Scene s = loadSceneFromString(
      std::string(kStaticBox) + kLoad + assimilation(kForceX, kCloud), "scene.yaml", dir.string());
  const PointCloudSettings& pc = *s.assimilation->observations.pointCloud;
  EXPECT_EQ(pc.present, (std::vector<bool>{false, true, false, true, false}));
  EXPECT_EQ(pc.frames[3].rows(), 12);  // the two points that are not finite dropped
  ASSERT_EQ(s.assimilation->notices.size(), 3u);
  EXPECT_EQ(s.assimilation->notices[0], "pc3.txt: 2 points not finite (line 13 first), dropped");
  EXPECT_EQ(s.assimilation->notices[1], "pc2.txt: no point; step 2 is a prediction only");
  EXPECT_EQ(s.assimilation->notices[2],
            "pc4.txt: 3 points, fewer than point_cloud.min_points (10); step 4 is a prediction "
            "only");
}

TEST(PointCloudScene, ACsvWithATimeColumnGoesToTheStepsOfItsTimes) {
  const fs::path dir = test::freshDir();
  std::string csv = "time,x,y,z\n";
  for (double t : {2.0, 1.0})
    for (int i = 0; i < 12; ++i)
      csv += std::to_string(t) + "," + std::to_string(0.005 + 0.007 * i) + ",0.01,0.02\n";
  writeText(dir / "cloud.csv", csv);
  const Scene s =
      loadSceneFromString(std::string(kStaticBox) + kLoad +
                              assimilation(kForceX, "    point_cloud: {csv: cloud.csv}\n"),
                          "scene.yaml", dir.string());
  const PointCloudSettings& pc = *s.assimilation->observations.pointCloud;
  EXPECT_EQ(pc.present, (std::vector<bool>{false, true, true, false, false}));
  ASSERT_EQ(s.assimilation->notices.size(), 1u);
  EXPECT_EQ(s.assimilation->notices[0].rfind("cloud.csv:14: time 1", 0), 0u)
      << s.assimilation->notices[0];
}

}  // namespace
}  // namespace bcassim
