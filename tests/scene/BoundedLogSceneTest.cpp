// The scene key of transform bounded-log (issue 15): lower and upper read in the parameter's
// unit, and its errors name line and key.
#include <gtest/gtest.h>

#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

// A static box with one load whose x force (N) is estimated: parameter line 8 of the file.
std::string boundedLogScene(const std::string& parameter) {
  return "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [5, 1, 1]}\n"
         "integrator: {type: static}\n"
         "time: {dt: 1, steps: 4}\n"
         "fixed: [{region: {half_space: {point: [0.001, 0, 0], normal: [-1, 0, 0]}}}]\n"
         "loads: [{region: {nodes: [20, 21]}, total_force: [0, 0, 0]}]\n"
         "assimilation:\n  parameters:\n    - {force: {load: 0, component: x}, " +
         parameter + "}\n  observations:\n    tracks: t.csv\n";
}

std::string boundedLogSceneError(const std::string& yaml) {
  try {
    loadSceneFromString(yaml, "scene.yaml", test::freshDir().string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BoundedLogScene, BoundsAreReadAndChecked) {
  EXPECT_EQ(boundedLogSceneError(
                boundedLogScene("mean: 2, stddev: 1, transform: bounded-log, lower: 0, upper: 8")),
            "scene.yaml:8: assimilation.parameters[0].lower: must be > 0 newtons, got 0");
  EXPECT_EQ(boundedLogSceneError(
                boundedLogScene("mean: 2, stddev: 1, transform: bounded-log, lower: 4, upper: 3")),
            "scene.yaml:8: assimilation.parameters[0].upper: must be > lower (4), got 3");
  EXPECT_EQ(boundedLogSceneError(boundedLogScene(
                "mean: 8, stddev: 1, transform: bounded-log, lower: 0.5, upper: 8")),
            "scene.yaml:8: assimilation.parameters[0].mean: 8 is outside the range of transform "
            "bounded-log");
  EXPECT_EQ(
      boundedLogSceneError(
          boundedLogScene("mean: 2, stddev: 1, transform: bounded-log, lower: 0.5")),
      "scene.yaml:8: assimilation.parameters[0]: transform bounded-log needs lower and upper");
  EXPECT_EQ(boundedLogSceneError(boundedLogScene("mean: 2, stddev: 1, transform: log, lower: 0.5")),
            "scene.yaml:8: assimilation.parameters[0].lower: only for transform projection or "
            "bounded-log");
}

}  // namespace
}  // namespace bcassim
