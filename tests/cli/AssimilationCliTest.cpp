// `bcassim assimilate` and `validate` as a user meets them: one-line located errors with exit
// code 2 for a malformed assimilation section, a run's summary and files, and the validation
// tracks written by `simulate`.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "bcassim/io/CsvTracks.h"
#include "support/BentBeamScene.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::runBcassim;
using test::writeText;

// Two markers on a small beam; line 6 opens the assimilation section.
const char* kScene =
    "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n"
    "markers:\n"
    "  - points: [[0.1, 0.01, 0.01], [0.05, 0.01, 0.01]]\n"
    "time: {dt: 0.01, steps: 3}\n"
    "output: {pvd: false}\n"
    "assimilation:\n";

const char* kTwoMarkers =
    "time,marker,x,y,z\n"
    "0.01,0,0.1,0.01,0.01\n0.01,1,0.05,0.01,0.01\n"
    "0.02,0,0.1,0.01,0.01\n0.02,1,0.05,0.01,0.01\n";

test::CliResult assimilate(const std::filesystem::path& dir, const std::string& section,
                           const std::string& tracks = kTwoMarkers) {
  writeText(dir / "scene.yaml", std::string(kScene) + section);
  writeText(dir / "tracks.csv", tracks);
  return runBcassim(dir, "assimilate scene.yaml --out out --quiet --no-plots");
}

void expectError(const test::CliResult& r, const std::string& message) {
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: " + message + "\n");
  EXPECT_EQ(r.out, "");
}

const char* kParameters =
    "  parameters:\n"
    "    - {young_modulus: {region: 0}, mean: 4000, stddev: 1000}\n";

// An assimilation section: the given options, then one parameter and the tracks.csv observations.
std::string sectionWith(const std::string& options) {
  return options + kParameters + "  observations: {tracks: tracks.csv}\n";
}

// A forecast that inverts an element whatever its step (min_dt = dt: no halving) stops the run
// with exit code 3 and one line naming the scene, the filter step, its time and the element.
TEST(AssimilationCli, FailedForecastNamesTheStepTimeAndElement) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml",
            "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n"
            "fixed: [{region: {box: {min: [-1, -1, -1], max: [0.001, 1, 1]}}}]\n"
            "loads: [{region: {box: {min: [0.099, -1, -1], max: [1, 1, 1]}}, "
            "total_force: [0, -1000, 0]}]\n"
            "markers:\n"
            "  - points: [[0.1, 0.01, 0.01], [0.05, 0.01, 0.01]]\n"
            "time: {dt: 0.01, steps: 3, min_dt: 0.01}\n"
            "output: {pvd: false}\n"
            "assimilation:\n" +
                sectionWith(""));
  writeText(dir / "tracks.csv", kTwoMarkers);
  const test::CliResult r = runBcassim(dir, "assimilate scene.yaml --out out --quiet --no-plots");
  EXPECT_EQ(r.exitCode, 3);
  const std::string prefix =
      "bcassim: error: scene.yaml: assimilation step 1 (t = 0.01 s), a forecast: element ";
  EXPECT_EQ(r.err.substr(0, prefix.size()), prefix) << r.err;
  EXPECT_NE(r.err.find(" inverted (det F = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(time.min_dt = 0.01 s allows no halving) (the last of 4 tries, the "
                       "sigma points at 1/8 of their spread)\n"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// The last row's mean of estimates.csv (one parameter).
double finalEstimate(const std::filesystem::path& estimates) {
  const std::string text = test::readText(estimates);
  const size_t lastRow = text.rfind('\n', text.size() - 2) + 1;
  const size_t meanAt = text.find(',', text.find(',', text.find(',', lastRow) + 1) + 1) + 1;
  return std::stod(text.substr(meanAt));
}

// The cantilever pulled by 10 N (E = 8,000 Pa in the truth) with a prior of 4,000 ± 3,500 Pa:
// the simplex sigma point at 500 Pa inverts an element even at time.min_dt, the mean does not.
// The step is redone with the points at 1/2 of their spread (500 -> 2,250 Pa) and the run goes
// on, with one notice; those are the points of a prior of ± 1,750 Pa, whose run needs no retry
// and, the data outweighing either prior after the first correction, ends at the same estimate.
// Without retries the run stops at that step.
TEST(AssimilationCli, AFailedForecastIsRedoneCloserToTheMeanAndTheRunGoesOn) {
  const auto dir = freshDir();
  const std::string beam = test::pulledCantileverScene();
  const auto estimate = [&](const std::string& options, double stddev) {
    return beam + "assimilation:\n" + options +
           fmt::format(
               "  parameters:\n    - {{young_modulus: {{region: 0}}, mean: 4000, stddev: "
               "{}}}\n  observations: {{tracks: truth/markers.csv}}\n",
               stddev);
  };
  writeText(dir / "truth.yaml", beam);
  writeText(dir / "wide.yaml", estimate("", 3500));
  writeText(dir / "narrow.yaml", estimate("", 1750));
  writeText(dir / "never.yaml", estimate("  forecast_retries: 0\n", 3500));
  ASSERT_EQ(runBcassim(dir, "simulate truth.yaml --out truth -q").exitCode, 0);
  const std::string run = " --quiet --no-plots";

  const test::CliResult wide = runBcassim(dir, "assimilate wide.yaml --out wide" + run);
  ASSERT_EQ(wide.exitCode, 0) << wide.err;
  const std::string notices = test::readText(dir / "wide" / "notices.txt");
  const std::string begins =
      "wide.yaml: assimilation step 1 (t = 0.01 s): implicit Euler at t = 0 s: element ";
  const std::string ends =
      "(time.min_dt = 0.01 s allows no halving); the step's forecasts were redone with the sigma "
      "points at 1/2 of their spread from the mean\n";
  EXPECT_EQ(notices.substr(0, begins.size()), begins) << notices;
  ASSERT_GE(notices.size(), ends.size()) << notices;
  EXPECT_EQ(notices.substr(notices.size() - ends.size()), ends) << notices;
  EXPECT_EQ(std::count(notices.begin(), notices.end(), '\n'), 1) << notices;

  ASSERT_EQ(runBcassim(dir, "assimilate narrow.yaml --out narrow" + run).exitCode, 0);
  EXPECT_EQ(test::readText(dir / "narrow" / "notices.txt"), "");
  const double a = finalEstimate(dir / "wide" / "estimates.csv");
  const double b = finalEstimate(dir / "narrow" / "estimates.csv");
  EXPECT_NEAR(a, b, 1e-3 * b);
  EXPECT_GT(a, 4000.0);  // moved from the prior towards the truth (8,000 Pa)

  const test::CliResult never = runBcassim(dir, "assimilate never.yaml --out never" + run);
  EXPECT_EQ(never.exitCode, 3);
  const std::string stops =
      "bcassim: error: never.yaml: assimilation step 1 (t = 0.01 s), a forecast: element ";
  EXPECT_EQ(never.err.substr(0, stops.size()), stops) << never.err;
  EXPECT_EQ(never.err.find("tries"), std::string::npos) << never.err;
}

TEST(AssimilationCli, ForecastRetriesAreACountFrom0To20) {
  const auto dir = freshDir();
  expectError(assimilate(dir, sectionWith("  forecast_retries: -1\n")),
              "scene.yaml:7: assimilation.forecast_retries: must be >= 0, got -1");
  expectError(assimilate(dir, sectionWith("  forecast_retries: 21\n")),
              "scene.yaml:7: assimilation.forecast_retries: must be <= 20 (the sigma points at "
              "1/2^20 of their spread), got 21");
}

TEST(AssimilationCli, ReforecastsAreForStaticFramesWithRoukf) {
  const auto dir = freshDir();
  expectError(assimilate(dir, sectionWith("  reforecasts: -1\n")),
              "scene.yaml:7: assimilation.reforecasts: must be >= 0, got -1");
  expectError(assimilate(dir, sectionWith("  reforecasts: 21\n")),
              "scene.yaml:7: assimilation.reforecasts: must be <= 20, got 21");
  expectError(assimilate(dir, sectionWith("  filter: ukf\n  reforecasts: 2\n")),
              "scene.yaml:8: assimilation.reforecasts: needs filter: roukf, got ukf");
  expectError(assimilate(dir, sectionWith("  reforecasts: 2\n")),
              "scene.yaml:7: assimilation.reforecasts: needs integrator.type static (a dynamic "
              "step has no equilibrium to re-centre on)");
  expectError(assimilate(dir, sectionWith("  reforecast_beyond: 2\n")),
              "scene.yaml:7: assimilation.reforecast_beyond: only for reforecasts > 0");
}

TEST(AssimilationCli, UnknownFilter) {
  const auto dir = freshDir();
  expectError(assimilate(dir, sectionWith("  filter: kalman\n")),
              "scene.yaml:7: assimilation.filter: expected one of ukf, roukf, etkf, got 'kalman'");
}

TEST(AssimilationCli, SigmaSpreadOnlyForUkfAndPositive) {
  const auto dir = freshDir();
  expectError(assimilate(dir, sectionWith("  filter: roukf\n  sigma_spread: 0.1\n")),
              "scene.yaml:8: assimilation.sigma_spread: only for filter ukf");
  expectError(assimilate(dir, sectionWith("  filter: ukf\n  sigma_spread: 0\n")),
              "scene.yaml:8: assimilation.sigma_spread: must be > 0, got 0");
}

TEST(AssimilationCli, MissingTracksFile) {
  const auto dir = freshDir();
  expectError(assimilate(dir, std::string(kParameters) + "  observations: {tracks: gone.csv}\n"),
              "scene.yaml:9: assimilation.observations.tracks: cannot open '" +
                  (dir / "gone.csv").string() + "'");
}

TEST(AssimilationCli, MarkerCountMismatch) {
  const auto dir = freshDir();
  expectError(assimilate(dir, std::string(kParameters) + "  observations: {tracks: tracks.csv}\n",
                         std::string(kTwoMarkers) + "0.02,2,0.1,0.01,0.01\n"),
              "scene.yaml:9: assimilation.observations.tracks: '" + (dir / "tracks.csv").string() +
                  "' holds 3 points (1 + largest marker index); the scene has 2 markers");
}

TEST(AssimilationCli, TracksOffTheTimeGrid) {
  const auto dir = freshDir();
  expectError(assimilate(dir, std::string(kParameters) + "  observations: {tracks: tracks.csv}\n",
                         "time,marker,x,y,z\n0.015,0,0.1,0.01,0.01\n0.015,1,0.05,0.01,0.01\n"),
              "scene.yaml:9: assimilation.observations.tracks: '" + (dir / "tracks.csv").string() +
                  "': frame at time 0.015 s is not on the scene's time grid 0 s + k x 0.01 s "
                  "(time.dt); the tracks must come from a run with the same dt");
}

TEST(AssimilationCli, MissingParameterMean) {
  const auto dir = freshDir();
  expectError(assimilate(dir,
                         "  parameters:\n    - {spring: {group: 0}, stddev: 1}\n"
                         "  observations: {tracks: tracks.csv}\n"),
              "scene.yaml:8: assimilation.parameters[0].spring.group: the scene has no springs");
}

TEST(AssimilationCli, InflationOnlyForUkfAndEtkf) {
  const auto dir = freshDir();
  expectError(assimilate(dir, sectionWith("  inflation: 0.1\n")),
              "scene.yaml:7: assimilation.inflation: only for filters ukf and etkf (roukf keeps "
              "its rank)");
}

TEST(AssimilationCli, TangentOptionsNeedTheMeanTangent) {
  const auto dir = freshDir();
  expectError(assimilate(dir, sectionWith("  tangent_background: true\n")),
              "scene.yaml:7: assimilation.tangent_background: only for tangent: mean");
  expectError(assimilate(dir, sectionWith("  tangent_precision: single\n")),
              "scene.yaml:7: assimilation.tangent_precision: only for tangent: mean");
  expectError(assimilate(dir, sectionWith("  tangent: mean\n  tangent_precision: half\n")),
              "scene.yaml:8: assimilation.tangent_precision: expected one of double, single, got "
              "'half'");
  expectError(assimilate(dir, sectionWith("  tangent: mean\n  tangent_background_steps: 1\n")),
              "scene.yaml:8: assimilation.tangent_background_steps: only for tangent_background: "
              "true");
  expectError(assimilate(dir, sectionWith("  tangent: mean\n  tangent_background: true\n"
                                          "  tangent_refresh_every: 2\n"
                                          "  tangent_background_steps: 3\n")),
              "scene.yaml:10: assimilation.tangent_background_steps: 3 is more than "
              "tangent_refresh_every (2): a build is adopted at the latest when the next one is "
              "due");
  expectError(assimilate(dir, sectionWith("  tangent: mean\n  tangent_background: true\n"
                                          "  tangent_background_steps: 0\n")),
              "scene.yaml:9: assimilation.tangent_background_steps: must be >= 1, got 0");
  expectError(assimilate(dir, sectionWith("  tangent: frozen\n")),
              "scene.yaml:7: assimilation.tangent: expected one of own, mean, got 'frozen'");
}

TEST(AssimilationCli, MeanTangentRefusesMoreSpringsThanItCorrects) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml",
            "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [20, 4, 4]}\n"
            "springs:\n  groups: [{coefficients: [0, 0, 10]}]\n"
            "  attachments: [{region: {box: {min: [-1, -1, -1], max: [1, 1, 1]}}}]\n"
            "markers:\n  - points: [[0.1, 0.01, 0.01]]\n"
            "time: {dt: 0.01, steps: 3}\n"
            "assimilation:\n"
            "  tangent: mean\n"
            "  parameters: [{spring: {group: 0, coefficient: gamma}, mean: 10, stddev: 1}]\n"
            "  observations: {tracks: tracks.csv}\n");
  writeText(dir / "tracks.csv", "time,marker,x,y,z\n0.01,0,0.1,0.01,0.01\n");
  const test::CliResult r = runBcassim(dir, "assimilate scene.yaml --out out --quiet --no-plots");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err,
            "bcassim: error: scene.yaml:9: assimilation.tangent: mean corrects at most 128 springs "
            "exactly (the springs' stiffness is each sigma point's own); this scene has 354: use "
            "tangent: own\n");
}

TEST(AssimilationCli, RunPrintsSummaryAndWritesFiles) {
  const auto dir = freshDir();
  const test::CliResult r = assimilate(
      dir, std::string(kParameters) + "  observations: {tracks: tracks.csv, until_step: 2}\n");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("E_0"), std::string::npos);
  EXPECT_NE(r.out.find("no validation"), std::string::npos);
  for (const char* f : {"estimates.csv", "parameters.csv", "timing.csv", "filter.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / f)) << f;
  // Step 3 has no frame: a prediction only.
  EXPECT_NE(test::readText(dir / "out" / "filter.csv").find("\n3,0.03,0,0,0\n"), std::string::npos);

  // validate needs the truth of validation points.
  const test::CliResult v =
      runBcassim(dir, "validate scene.yaml --estimates out/estimates.csv --out val --no-plots");
  expectError(v,
              "scene.yaml: assimilation.validation.tracks: missing (truth of the validation "
              "points)");
}

TEST(AssimilationCli, SimulateWritesValidationTracksFromRest) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml",
            "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n"
            "validation_points: {points: [[0.1, 0.01, 0.01]]}\n"
            "time: {dt: 0.01, steps: 2}\noutput: {pvd: false}\n");
  const test::CliResult r = runBcassim(dir, "simulate scene.yaml --out out --quiet");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  // Frame 0 is the rest state: displacements of the truth are measured from it.
  const MarkerTracks t = readMarkerTracks((dir / "out" / "validation.csv").string());
  ASSERT_EQ(t.times.size(), 3u);
  EXPECT_EQ(t.numMarkers, 1);
  EXPECT_EQ(t.times[0], 0.0);
  EXPECT_NEAR(t.times[2], 0.02, 1e-12);
  EXPECT_NEAR((t.frames[0].row(0) - Eigen::RowVector3d(0.1, 0.01, 0.01)).norm(), 0.0, 1e-12);
}

TEST(AssimilationCli, ValidationPointsNeedOneSource) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml",
            "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n"
            "validation_points: {nodes: some}\n");
  expectError(runBcassim(dir, "simulate scene.yaml --out out --quiet"),
              "scene.yaml:2: validation_points.nodes: expected 'all' (every mesh node), got "
              "'some'");
}

// A beam bent by a tip load: the truth with E = 5,000 Pa, the estimation starting from 4,000 Pa.
std::string bentBeam(double youngModulus) {
  return test::bentBeamScene(youngModulus, "pvd: false");
}

TEST(AssimilationCli, ThreadsOverrideTheSceneAndLeaveTheEstimatesAlone) {
  const auto dir = freshDir();
  writeText(dir / "truth.yaml", bentBeam(5000));
  writeText(dir / "estimate.yaml", bentBeam(4000) + "assimilation:\n  threads: 1\n" + kParameters +
                                       "  observations: {tracks: truth/markers.csv}\n");
  ASSERT_EQ(runBcassim(dir, "simulate truth.yaml --out truth -q").exitCode, 0);
  const test::CliResult scene =
      runBcassim(dir, "assimilate estimate.yaml --out scene -q --no-plots");
  EXPECT_NE(scene.out.find(", filter roukf, 1 thread, 6 steps"), std::string::npos) << scene.out;
  const test::CliResult one =
      runBcassim(dir, "assimilate estimate.yaml --out one --threads 1 -q --no-plots");
  const test::CliResult two =
      runBcassim(dir, "assimilate estimate.yaml --out two --threads 2 -q --no-plots");
  ASSERT_EQ(one.exitCode, 0) << one.err;
  ASSERT_EQ(two.exitCode, 0) << two.err;
  EXPECT_NE(one.out.find(", 1 thread (--threads; the scene says 1), "), std::string::npos)
      << one.out;
  EXPECT_NE(two.out.find(", 2 threads (--threads; the scene says 1), "), std::string::npos)
      << two.out;
  // The sigma points' forecasts are independent: how many threads run them changes nothing.
  const std::string estimates = test::readText(dir / "one" / "estimates.csv");
  EXPECT_EQ(estimates, test::readText(dir / "two" / "estimates.csv"));
  EXPECT_EQ(test::readText(dir / "one" / "filter.csv"), test::readText(dir / "two" / "filter.csv"));
  // ... and the filter did its work: the last estimate is the truth's modulus.
  const std::string last = estimates.substr(estimates.rfind('\n', estimates.size() - 2) + 1);
  ASSERT_EQ(last.rfind("6,0.3,E_0,", 0), 0u) << last;
  EXPECT_NEAR(std::stod(last.substr(10)), 5000.0, 50.0) << last;
}

}  // namespace
}  // namespace bcassim
