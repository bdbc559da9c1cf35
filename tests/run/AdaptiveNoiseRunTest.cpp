// observations.adaptive_noise end to end (issue 15): tracks with 1 mm of noise added, the filter
// assuming 0.1 mm at first, finds the noise and writes it step by step to noise.csv; a stopped and
// resumed run continues the estimator's window from its checkpoint.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/SimulationRunner.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/PulledCylinderScene.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

std::string adaptiveNoiseCylinder(const std::string& material, const std::string& extra,
                                  int steps) {
  return test::pulledCylinderScene(200, material + "solver: {type: cholmod}\n", steps, 10,
                                   "output: {pvd: false}\n") +
         "fixed:\n"
         "  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
         "  - region: {half_space: {point: [0, 0, 0.1799], normal: [0, 0, 1]}}\n" +
         extra;
}

// Column `column` of noise.csv, one value per row.
std::vector<double> adaptiveNoiseColumn(const std::filesystem::path& csv, int column) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string field;
    for (int i = 0; i <= column; ++i) std::getline(s, field, ',');
    out.push_back(std::stod(field));
  }
  return out;
}

TEST(AdaptiveNoiseRun, FindsTheTracksNoiseAndResumesItsWindow) {
  const auto dir = test::freshDir();
  const int steps = 80;
  runSimulation(
      loadSceneFromString(
          adaptiveNoiseCylinder(
              "material: {model: stvk, young_modulus: 8000, poisson_ratio: 0.45}\n", "", steps),
          "truth.yaml", dir.string()),
      (dir / "truth").string());
  const Scene scene = loadSceneFromString(
      adaptiveNoiseCylinder("material: {model: stvk, young_modulus: 5000, poisson_ratio: 0.45}\n",
                            "assimilation:\n"
                            "  filter: roukf\n"
                            "  reuse_factorization: false\n"
                            "  parameters:\n"
                            "    - {name: E, young_modulus: {region: 0}, mean: 5000, stddev: "
                            "2000, transform: log}\n"
                            "  observations:\n"
                            "    tracks: truth/markers.csv\n"
                            "    noise_stddev: 1.0e-3\n"
                            "    sigma: 1.0e-4\n"
                            "    adaptive_noise: {window: 30, floor: 1.0e-5}\n",
                            steps),
      "estimate.yaml", dir.string());
  const auto whole = dir / "whole", stopped = dir / "stopped";
  const AssimilationResult a = runAssimilation(scene, whole.string());
  const std::string noise = test::readText(whole / "noise.csv");
  EXPECT_EQ(noise.substr(0, noise.find('\n')),
            "step,time_s,observed_entries,sigma_m,estimated_sigma_m,innovation_squared_norm_m2,"
            "predicted_observation_trace_m2");
  EXPECT_EQ(test::countLines(noise), 1 + steps);
  const std::vector<double> used = adaptiveNoiseColumn(whole / "noise.csv", 3),
                            estimated = adaptiveNoiseColumn(whole / "noise.csv", 4);
  ASSERT_EQ(estimated.size(), static_cast<size_t>(steps));
  EXPECT_DOUBLE_EQ(used.front(), 1e-4);  // the scene's sigma, then each step the one before's
  for (int i = 1; i < steps; ++i)
    EXPECT_DOUBLE_EQ(used[static_cast<size_t>(i)], estimated[static_cast<size_t>(i - 1)]);
  std::cout << "[ adaptive run ] sigma after " << steps << " steps: " << estimated.back()
            << " m (noise added 1e-3 m, assumed 1e-4 m at first); E = " << a.parameters[0].mean
            << " Pa (truth 8000)\n";
  EXPECT_NEAR(estimated.back(), 1e-3, 0.1e-3);
  EXPECT_NEAR(a.parameters[0].mean, 8000.0, 0.1 * 8000.0);

  struct Stop {};
  EXPECT_THROW(runAssimilation(scene, stopped.string(),
                               [](const AssimilationProgress& p) {
                                 if (p.step == 47) throw Stop{};
                               }),
               Stop);
  runAssimilation(scene, stopped.string(), {}, true);
  for (const char* f : {"noise.csv", "estimates.csv", "filter.csv"})
    EXPECT_EQ(test::readText(stopped / f), test::readText(whole / f)) << f;
}

}  // namespace
}  // namespace bcassim
