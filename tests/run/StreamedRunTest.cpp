// A run fed through an AssimilationStream (what `bcassim serve` does) against the same run
// reading the tracks file: the same files byte for byte, one publication per step with the
// hidden points of hidden_points.csv; the stream's end ends the run with whole files; a scene
// whose tracks are `stream` is refused by a run without one.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/BentBeamScene.h"
#include "support/PulledCylinderScene.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::readText;

constexpr int kStreamedSteps = 24;

std::string streamedCylinder(const std::string& material, const std::string& extra) {
  return test::pulledCylinderScene(150, material, kStreamedSteps, 4,
                                   "output: {pvd: false, every: 10}\n") +
         "fixed:\n"
         "  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
         "hidden_points: {points: [[0, 0, 0.09], [0.005, 0, 0.12]]}\n" +
         extra;
}

std::string streamedEstimation(const std::string& tracks) {
  return streamedCylinder(
      "material: {model: stvk, young_modulus: 5000, poisson_ratio: 0.45}\n"
      "solver: {type: factorized-pcg}\n",
      "assimilation:\n  parameters:\n"
      "    - {name: E, young_modulus: {region: 0}, mean: 5000, stddev: 2000, transform: log}\n"
      "  observations: {tracks: " +
          tracks + ", noise_stddev: 1.0e-4, sigma: 1.0e-4}\n");
}

TEST(StreamedRun, SameFilesAsTheTracksFileAndEndsWhenTheStreamDoes) {
  const auto dir = freshDir();
  runSimulation(loadSceneFromString(
                    streamedCylinder("material: {model: stvk, young_modulus: 8000, poisson_ratio: "
                                     "0.45}\nsolver: {type: cholmod}\n",
                                     ""),
                    "truth.yaml", dir.string()),
                (dir / "truth").string());
  const Scene scene =
      loadSceneFromString(streamedEstimation("truth/markers.csv"), "estimate.yaml", dir.string());
  runAssimilation(scene, (dir / "file").string());

  // The stream hands over the file's frames (none where the file has none).
  const TrackFrames& tracks = scene.assimilation->observations.tracks;
  std::vector<StepPublication> published;
  std::vector<std::vector<HiddenPointPrediction>> hidden;
  AssimilationStream stream;
  stream.frame = [&](int step) {
    if (!tracks.present[static_cast<size_t>(step)]) return StreamedFrame{};
    return StreamedFrame{StreamedFrame::Kind::Observed, tracks.frames[static_cast<size_t>(step)]};
  };
  stream.publish = [&](const StepPublication& p) {
    ASSERT_NE(p.nodePositions, nullptr);
    EXPECT_EQ(p.nodePositions->size(), 3 * scene.model.mesh->numNodes());
    published.push_back(p);
    hidden.push_back(p.hidden);
  };
  runAssimilation(scene, (dir / "streamed").string(), {}, false, &stream);
  for (const char* f : {"estimates.csv", "filter.csv", "hidden_points.csv", "parameters.csv"})
    EXPECT_EQ(readText(dir / "file" / f), readText(dir / "streamed" / f)) << f;
  ASSERT_EQ(published.size(), static_cast<size_t>(kStreamedSteps));
  for (int k = 0; k < kStreamedSteps; ++k) {
    EXPECT_EQ(published[static_cast<size_t>(k)].step, k + 1);
    ASSERT_EQ(hidden[static_cast<size_t>(k)].size(), 2u);
    EXPECT_GT(hidden[static_cast<size_t>(k)][0].radius95Total, 0.0);
  }

  // The stream ends after step 10: ten steps, every file whole.
  stream.frame = [&](int step) {
    if (step > 10) return StreamedFrame{StreamedFrame::Kind::End, {}};
    return StreamedFrame{StreamedFrame::Kind::Observed, tracks.frames[static_cast<size_t>(step)]};
  };
  published.clear();
  const AssimilationResult r = runAssimilation(scene, (dir / "ended").string(), {}, false, &stream);
  EXPECT_EQ(r.steps, 10);
  EXPECT_EQ(published.size(), 10u);
  const std::string full = readText(dir / "file" / "hidden_points.csv");
  const std::string ended = readText(dir / "ended" / "hidden_points.csv");
  // Steps 0..10, two points each, plus the header.
  EXPECT_EQ(std::count(ended.begin(), ended.end(), '\n'), 1 + 11 * 2);
  EXPECT_EQ(full.substr(0, ended.size()), ended);
}

// A step redone closer to the mean (the pulled cantilever's low-modulus sigma point inverts an
// element) is said to the stream as it is written to notices.txt: `bcassim serve` logs it live.
TEST(StreamedRun, NoticesReachTheStreamAsTheyAreWritten) {
  const auto dir = freshDir();
  runSimulation(loadSceneFromString(test::pulledCantileverScene(), "truth.yaml", dir.string()),
                (dir / "truth").string());
  const Scene scene =
      loadSceneFromString(test::pulledCantileverScene() +
                              "assimilation:\n  parameters:\n"
                              "    - {young_modulus: {region: 0}, mean: 4000, stddev: 3500}\n"
                              "  observations: {tracks: truth/markers.csv}\n",
                          "estimate.yaml", dir.string());
  const TrackFrames& tracks = scene.assimilation->observations.tracks;
  AssimilationStream stream;
  stream.frame = [&](int step) {
    return StreamedFrame{StreamedFrame::Kind::Observed, tracks.frames[static_cast<size_t>(step)]};
  };
  stream.publish = [](const StepPublication&) {};
  std::string said;
  stream.notice = [&](const std::string& line) { said += line + "\n"; };
  runAssimilation(scene, (dir / "streamed").string(), {}, false, &stream);
  const std::string written = readText(dir / "streamed" / "notices.txt");
  EXPECT_NE(written.find("the step's forecasts were redone"), std::string::npos) << written;
  EXPECT_EQ(said, written);
}

TEST(StreamedRun, ModelErrorIsGrowsOrConstant) {
  const auto dir = freshDir();
  std::string yaml = streamedEstimation("stream");
  EXPECT_TRUE(loadSceneFromString(yaml, "estimate.yaml", dir.string())
                  .assimilation->observations.modelErrorGrows);
  yaml.replace(yaml.find("sigma: 1.0e-4}"), 14, "sigma: 1.0e-4, model_error: sometimes}");
  try {
    loadSceneFromString(yaml, "estimate.yaml", dir.string());
    FAIL() << "loaded";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "estimate.yaml:21: assimilation.observations.model_error: expected one of "
                 "grows, constant, got 'sometimes'");
  }
}

TEST(StreamedRun, StreamTracksNeedAStream) {
  const auto dir = freshDir();
  const Scene scene =
      loadSceneFromString(streamedEstimation("stream"), "estimate.yaml", dir.string());
  EXPECT_TRUE(scene.assimilation->observations.streamed);
  try {
    runAssimilation(scene, (dir / "out").string());
    FAIL() << "ran";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "estimate.yaml: assimilation.observations.tracks: stream: the markers come from "
                 "`bcassim serve` (OpenIGTLink); to assimilate, name a tracks file");
  }
}

}  // namespace
}  // namespace bcassim
