// Markers streamed to `bcassim serve` in a camera's frame: with observations.frame_transform the
// intake hands them to the filter in the model's frame, as an assimilate run reads a tracks file;
// a marker the frame does not carry stays unseen (NaN).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cmath>

#include "bcassim/navigation/FrameIntake.h"
#include "bcassim/scene/SceneLoader.h"
#include "bcassim/stream/IgtlMessages.h"
#include "bcassim/stream/TcpSocket.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

TEST(FrameIntake, StreamedMarkersAreMovedIntoTheModelsFrame) {
  const auto dir = test::freshDir();
  RigidTransform cameraToModel;
  cameraToModel.rotation = Eigen::AngleAxisd(1.1, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  cameraToModel.translation = Vec3(-0.2, 0.05, 0.3);
  std::string matrix;
  for (int r = 0; r < 3; ++r)
    matrix += fmt::format("{:.17g} {:.17g} {:.17g} {:.17g}\n", cameraToModel.rotation(r, 0),
                          cameraToModel.rotation(r, 1), cameraToModel.rotation(r, 2),
                          cameraToModel.translation(r));
  test::writeText(dir / "T.txt", matrix + "0 0 0 1\n");
  const Scene scene = loadSceneFromString(
      "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [5, 1, 1]}\n"
      "integrator: {type: static}\n"
      "time: {dt: 1, steps: 4}\n"
      "fixed: [{region: {half_space: {point: [0.001, 0, 0], normal: [-1, 0, 0]}}}]\n"
      "loads: [{region: {nodes: [20, 21]}, total_force: [0, 0, 0]}]\n"
      "markers: [{points: [[0.1, 0.01, 0.02], [0.1, 0.0, 0.0]]}]\n"
      "assimilation:\n"
      "  parameters: [{force: {load: 0, component: z}, mean: 0, stddev: 1}]\n"
      "  observations: {tracks: stream, frame_transform: T.txt}\n",
      "scene.yaml", dir.string());

  IgtlServer server("127.0.0.1", 0, {});
  const std::atomic<bool> interrupted{false};
  FrameIntake intake(scene, server, 0.0, 5.0, interrupted, {});
  const Vec3 model(0.1, 0.012, 0.021);  // m: marker 0, a little moved
  const Vec3 camera = cameraToModel.inverse().apply(model.transpose()).row(0).transpose();
  const TcpSocket client = TcpSocket::connectTo("127.0.0.1", server.port());
  const std::string message =
      encodeIgtlPoints("Markers", 1.0, "markers", {{"marker_0", camera, 0}});
  ASSERT_TRUE(client.writeAll(message.data(), message.size()));
  const std::optional<IntakeFrame> frame = intake.next(0);
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->step, 1);
  ASSERT_EQ(frame->markers.rows(), 2);
  // POINT messages carry float32 coordinates: ~1e-8 m at these distances.
  EXPECT_LT((frame->markers.row(0).transpose() - model).norm(), 1e-7);
  EXPECT_TRUE(frame->markers.row(1).hasNaN());
}

}  // namespace
}  // namespace bcassim
