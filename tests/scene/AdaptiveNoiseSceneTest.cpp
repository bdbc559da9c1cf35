// The scene key observations.adaptive_noise (issue 15): window and floor read with their defaults,
// and a bad value, an unknown key or a floor above sigma give one line naming line and key.
#include <gtest/gtest.h>

#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// A static box with one estimated load seen as a point cloud: `observations` goes on line 11.
std::string adaptiveNoiseScene(const std::string& observations) {
  return "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [5, 1, 1]}\n"
         "integrator: {type: static}\n"
         "time: {dt: 1, steps: 4}\n"
         "fixed: [{region: {half_space: {point: [0.001, 0, 0], normal: [-1, 0, 0]}}}]\n"
         "loads: [{region: {nodes: [20, 21]}, total_force: [0, 0, 0]}]\n"
         "assimilation:\n"
         "  parameters:\n"
         "    - {force: {load: 0, component: x}, mean: 0, stddev: 1}\n"
         "  observations:\n"
         "    point_cloud: {files: \"pc*.txt\"}\n" +
         observations;
}

fs::path adaptiveNoiseCloudDir() {
  const fs::path dir = test::freshDir();
  for (int k = 1; k <= 4; ++k) {
    std::string points;
    for (int i = 0; i < 12; ++i) points += std::to_string(0.005 + 0.007 * i) + " 0.01 0.02\n";
    test::writeText(dir / ("pc" + std::to_string(k) + ".txt"), points);
  }
  return dir;
}

std::string adaptiveNoiseSceneError(const std::string& observations) {
  try {
    loadSceneFromString(adaptiveNoiseScene(observations), "scene.yaml",
                        adaptiveNoiseCloudDir().string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(AdaptiveNoiseScene, WindowAndFloorAreRead) {
  const fs::path dir = adaptiveNoiseCloudDir();
  const Scene fixed =
      loadSceneFromString(adaptiveNoiseScene("    sigma: 2.0e-4\n"), "scene.yaml", dir.string());
  EXPECT_FALSE(fixed.assimilation->observations.adaptiveNoise);
  const Scene given = loadSceneFromString(
      adaptiveNoiseScene("    sigma: 2.0e-4\n    adaptive_noise: {window: 12, floor: 1.0e-5}\n"),
      "scene.yaml", dir.string());
  ASSERT_TRUE(given.assimilation->observations.adaptiveNoise);
  EXPECT_EQ(given.assimilation->observations.adaptiveNoise->window, 12);
  EXPECT_DOUBLE_EQ(given.assimilation->observations.adaptiveNoise->floor, 1e-5);
  EXPECT_DOUBLE_EQ(given.assimilation->observations.sigma, 2e-4);
  const Scene defaults = loadSceneFromString(adaptiveNoiseScene("    adaptive_noise: {}\n"),
                                             "scene.yaml", dir.string());
  ASSERT_TRUE(defaults.assimilation->observations.adaptiveNoise);
  EXPECT_EQ(defaults.assimilation->observations.adaptiveNoise->window, 30);
  EXPECT_DOUBLE_EQ(defaults.assimilation->observations.adaptiveNoise->floor, 1e-6);
}

TEST(AdaptiveNoiseScene, BadValuesNameLineAndKey) {
  EXPECT_EQ(adaptiveNoiseSceneError("    adaptive_noise: {window: 0}\n"),
            "scene.yaml:11: assimilation.observations.adaptive_noise.window: must be >= 1, got 0");
  EXPECT_EQ(adaptiveNoiseSceneError("    adaptive_noise: {window: 2.5}\n"),
            "scene.yaml:11: assimilation.observations.adaptive_noise.window: expected an "
            "integer, got '2.5'");
  EXPECT_EQ(adaptiveNoiseSceneError("    adaptive_noise: {floor: -1.0e-5}\n"),
            "scene.yaml:11: assimilation.observations.adaptive_noise.floor: must be > 0 metres, "
            "got -1.0e-5");
  EXPECT_EQ(adaptiveNoiseSceneError("    sigma: 1.0e-4\n    adaptive_noise: {floor: 1.0e-3}\n"),
            "scene.yaml:12: assimilation.observations.adaptive_noise.floor: must be <= "
            "observations.sigma (0.0001 metres), got 1.0e-3");
  EXPECT_EQ(adaptiveNoiseSceneError("    sigma: 1.0e-7\n    adaptive_noise: {window: 5}\n"),
            "scene.yaml:12: assimilation.observations.adaptive_noise.floor: must be <= "
            "observations.sigma (1e-07 metres), got 1e-06 (the default)");
  EXPECT_EQ(adaptiveNoiseSceneError("    adaptive_noise: {windows: 5}\n"),
            "scene.yaml:11: unknown key 'windows' in assimilation.observations.adaptive_noise; "
            "expected one of window, floor");
  EXPECT_EQ(adaptiveNoiseSceneError("    adaptive_noise: true\n"),
            "scene.yaml:11: assimilation.observations.adaptive_noise: expected a map of keys, "
            "got 'true'");
}

}  // namespace
}  // namespace bcassim
