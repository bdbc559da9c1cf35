// `bcassim assimilate --mpi` under mpirun (3 ranks, oversubscribed on a small machine): the same
// estimates as 1 and 2 threads, a worker's error as rank 0's one line, and a rank killed mid-run
// (BCASSIM_TEST_MPI_KILL) as one line naming the step, after which --resume finishes the run.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "bcassim/io/BinaryArchive.h"
#include "bcassim/run/AssimilationCheckpoint.h"
#include "support/BentBeamScene.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::readText;
using test::runBcassim;
using test::writeText;

// A beam bent by a tip load (20 nodes, 2 markers), 6 steps with a checkpoint every 2.
std::string mpiBeam(double youngModulus) {
  return test::bentBeamScene(youngModulus, "pvd: false, every: 2");
}

const char* kMpiParameter =
    "  parameters:\n"
    "    - {young_modulus: {region: 0}, mean: 4000, stddev: 1000, transform: log}\n"
    "  observations: {tracks: truth/markers.csv}\n";

// The three filters, each with settings whose threaded runs are exactly reproducible (a shared
// factorisation with tangent: own preconditions with whichever sigma point worker 0 ran last:
// equal to the PCG tolerance only, threads or ranks alike).
const char* kMpiRoukf = "assimilation:\n  sigma_points: star\n  tangent: mean\n";
const char* kMpiUkf =
    "assimilation:\n  filter: ukf\n  sigma_points: simplex\n  sigma_spread: 0.13\n"
    "  state: {positions: true, velocities: false}\n  reuse_factorization: false\n";
// Positions only with the mean's tangent: every worker continues its reference with the tangent
// of the step that ends (SharedFactorization::endStepTangent), whichever worker rebuilds it.
const char* kMpiUkfMeanTangent =
    "assimilation:\n  filter: ukf\n  sigma_points: simplex\n  sigma_spread: 0.13\n"
    "  state: {positions: true, velocities: false}\n  tangent: mean\n";
const char* kMpiEtkf =
    "assimilation:\n  filter: etkf\n  members: 7\n  reuse_factorization: false\n"
    "  state: {positions: true, velocities: true}\n";

// `bcassim args` in dir under mpirun with `ranks` ranks (0: alone, without mpirun);
// `environment` (NAME=VALUE) exported to every rank.
test::CliResult runMpiBcassim(const std::filesystem::path& dir, int ranks, const std::string& args,
                              const std::string& environment = "") {
  // Root needs mpirun's consent; --bind-to none lets each rank's threads use every core.
  const std::string options =
      std::string(geteuid() == 0 ? "--allow-run-as-root " : "") + "--oversubscribe --bind-to none";
  std::string exported;
  if (!environment.empty())
    exported = fmt::format("-x {} ", environment.substr(0, environment.find('=')));
  const std::string launcher =
      ranks == 0 ? "" : fmt::format("'{}' {} {}-np {}", BCASSIM_MPIEXEC, options, exported, ranks);
  // Under AddressSanitizer (make sanitize) OpenMPI's own allocations at MPI_Finalize are reported
  // as leaks, from components already unloaded (no module name to suppress): MPI runs go without
  // leak checking; the same code runs leak-checked in the threaded runs.
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string sanitizer =
      fmt::format("ASAN_OPTIONS='{}{}detect_leaks=0'", asan ? asan : "", asan && *asan ? ":" : "");
  const std::string cmd =
      fmt::format("cd '{}' && {} {} {} '{}' {} > cli.out 2> cli.err", dir.string(), sanitizer,
                  environment, launcher, BCASSIM_BINARY, args);
  const int status = std::system(cmd.c_str());
  test::CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readText(dir / "cli.out");
  r.err = readText(dir / "cli.err");
  return r;
}

// The lines of `text` that start with `prefix`.
std::vector<std::string> mpiLinesStartingWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  size_t at = 0;
  while (at < text.size()) {
    const size_t end = std::min(text.find('\n', at), text.size());
    if (text.compare(at, prefix.size(), prefix) == 0) lines.push_back(text.substr(at, end - at));
    at = end + 1;
  }
  return lines;
}

// The filter's state and the models' reference in a run's last checkpoint, full precision.
AssimilationCheckpoint mpiLastCheckpoint(const std::filesystem::path& out) {
  const std::string path = (out / "checkpoint.bin").string();
  ArchiveReader header(path, "the test's checkpoint");
  header.text();  // the magic
  return readAssimilationCheckpoint(path, header.text());
}

double mpiMaxRelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return INFINITY;
  double worst = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double scale = std::max(std::abs(a(i)), std::abs(b(i)));
    if (scale > 0) worst = std::max(worst, std::abs(a(i) - b(i)) / scale);
  }
  return worst;
}

// The largest entry difference over the largest entry of a: round-off in a covariance's
// near-zero entries is relative to the covariance, not to the entry.
double mpiNormwiseDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return INFINITY;
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : 0.0;
}

// Filter matrices and reference of two runs' last checkpoints: the largest relative difference,
// entry by entry or (`normwise`) matrix by matrix.
double mpiCheckpointDifference(const std::filesystem::path& a, const std::filesystem::path& b,
                               bool normwise = false) {
  const AssimilationCheckpoint ca = mpiLastCheckpoint(a), cb = mpiLastCheckpoint(b);
  EXPECT_EQ(ca.step, cb.step);
  EXPECT_EQ(ca.filter.matrices.size(), cb.filter.matrices.size());
  const auto difference = normwise ? mpiNormwiseDifference : mpiMaxRelativeDifference;
  double worst = difference(ca.reference.x, cb.reference.x);
  for (size_t i = 0; i < std::min(ca.filter.matrices.size(), cb.filter.matrices.size()); ++i)
    worst = std::max(worst, difference(ca.filter.matrices[i], cb.filter.matrices[i]));
  return worst;
}

// truth/ (E = 5,000 Pa) and estimate.yaml (from 4,000 Pa) with `section`.
std::filesystem::path mpiSceneDir(const std::string& section) {
  const auto dir = freshDir();
  writeText(dir / "truth.yaml", mpiBeam(5000));
  writeText(dir / "estimate.yaml", mpiBeam(4000) + section + kMpiParameter);
  EXPECT_EQ(runBcassim(dir, "simulate truth.yaml --out truth -q").exitCode, 0);
  return dir;
}

// `normwise`: b's filter kept its covariance over the ranks (a full-state UKF: the mean and the
// Gram matrix summed in another order, ScaLAPACK's Cholesky, each rank's sigma points from its
// columns of the factor), so its state differs from a's by round-off, relative to each matrix.
void expectSameRuns(const std::filesystem::path& dir, const std::string& a, const std::string& b,
                    bool normwise = false) {
  EXPECT_EQ(readText(dir / a / "estimates.csv"), readText(dir / b / "estimates.csv")) << a << b;
  EXPECT_EQ(readText(dir / a / "filter.csv"), readText(dir / b / "filter.csv")) << a << b;
  const double difference = mpiCheckpointDifference(dir / a, dir / b, normwise);
  EXPECT_LE(difference, 1e-12) << a << " against " << b;
  std::printf("%s against %s: max relative difference of the filter state %.3g (%s)\n", a.c_str(),
              b.c_str(), difference, normwise ? "normwise" : "entrywise");
}

// With `keptOverRanks` (the UKF), runs on more than one rank are compared normwise.
void expectRanksMatchThreads(const std::string& section, bool keptOverRanks = false) {
  const auto dir = mpiSceneDir(section);
  const std::string run = "assimilate estimate.yaml -q --no-plots ";
  ASSERT_EQ(runBcassim(dir, run + "--out t1 --threads 1").exitCode, 0);
  ASSERT_EQ(runBcassim(dir, run + "--out t2 --threads 2").exitCode, 0);
  // One rank without mpirun (a singleton job): the threaded run.
  ASSERT_EQ(runMpiBcassim(dir, 0, run + "--out m1 --threads 1 --mpi").exitCode, 0);
  const test::CliResult three = runMpiBcassim(dir, 3, run + "--out m3 --threads 1 --mpi");
  ASSERT_EQ(three.exitCode, 0) << three.err;
  EXPECT_EQ(three.err, "");
  EXPECT_NE(three.out.find(", 3 MPI ranks x 1 thread (--threads; "), std::string::npos)
      << three.out;
  const test::CliResult twoByTwo = runMpiBcassim(dir, 2, run + "--out m2x2 --threads 2 --mpi");
  ASSERT_EQ(twoByTwo.exitCode, 0) << twoByTwo.err;
  expectSameRuns(dir, "t1", "t2");
  expectSameRuns(dir, "t1", "m1");
  expectSameRuns(dir, "t1", "m3", keptOverRanks);
  expectSameRuns(dir, "t1", "m2x2", keptOverRanks);
  if (keptOverRanks) {
    // Rank 0 says the covariance was kept over the ranks, and what each part cost.
    EXPECT_NE(three.out.find("MPI: covariance kept over the ranks, rank 0 per step after the "
                             "first: Cholesky "),
              std::string::npos)
        << three.out;
  }
}

TEST(MpiExecutor, RoukfOnThreeRanksGivesTheThreadedEstimates) {
  expectRanksMatchThreads(kMpiRoukf);
}
TEST(MpiExecutor, UkfOnThreeRanksGivesTheThreadedEstimates) {
  expectRanksMatchThreads(kMpiUkf, true);
}
TEST(MpiExecutor, UkfWithTheMeansTangentOnThreeRanksGivesTheThreadedEstimates) {
  expectRanksMatchThreads(kMpiUkfMeanTangent, true);
}
TEST(MpiExecutor, EtkfOnThreeRanksGivesTheThreadedEstimates) { expectRanksMatchThreads(kMpiEtkf); }
// Star points (each rank reads single columns of the factor, not a range and a suffix sum) and
// process noise (added to the diagonal of every rank's piece).
TEST(MpiExecutor, UkfWithStarPointsAndProcessNoiseOnThreeRanksGivesTheThreadedEstimates) {
  expectRanksMatchThreads(
      "assimilation:\n  filter: ukf\n  sigma_points: star\n  sigma_spread: 0.13\n"
      "  inflation: 0.02\n  state: {positions: true, velocities: false}\n"
      "  reuse_factorization: false\n",
      true);
}

// A full-state UKF with its sigma points sqrt(n) standard deviations out and no log transform:
// a sigma point of rank 2's block gets a negative modulus. Rank 0 prints the error once, naming
// the rank, with the exit code of the single-process run; no rank is left waiting.
TEST(MpiExecutor, AWorkersErrorIsRankZerosOneLine) {
  const auto dir = freshDir();
  writeText(dir / "truth.yaml", mpiBeam(5000));
  writeText(dir / "estimate.yaml",
            mpiBeam(4000) +
                "assimilation:\n  filter: ukf\n  sigma_points: simplex\n"
                "  state: {positions: true, velocities: false}\n  reuse_factorization: false\n"
                "  parameters:\n    - {young_modulus: {region: 0}, mean: 4000, stddev: 1000}\n"
                "  observations: {tracks: truth/markers.csv}\n");
  ASSERT_EQ(runBcassim(dir, "simulate truth.yaml --out truth -q").exitCode, 0);
  const test::CliResult alone =
      runBcassim(dir, "assimilate estimate.yaml --out alone -q --no-plots");
  const test::CliResult ranks =
      runMpiBcassim(dir, 3, "assimilate estimate.yaml --out ranks -q --no-plots --mpi");
  ASSERT_NE(alone.exitCode, 0);
  EXPECT_EQ(ranks.exitCode, alone.exitCode) << ranks.err;
  const std::string prefix = "bcassim: error: ";
  const std::vector<std::string> lines = mpiLinesStartingWith(ranks.err, prefix);
  ASSERT_EQ(lines.size(), 1u) << ranks.err;
  EXPECT_EQ(lines[0], prefix + "MPI rank 2: " +
                          alone.err.substr(prefix.size(), alone.err.size() - prefix.size() - 1))
      << ranks.err;
}

// Rank 2 killed (SIGKILL) when step 4's sigma points reach it: mpirun ends the job, rank 0 says
// in one line where the run stood; the same command with --resume continues from step 2's
// checkpoint and ends with the uninterrupted run's estimates (`keptOverRanks`, a UKF: to
// round-off, its covariance gathered into the checkpoint and scattered again). `owing`: the ranks
// the line names (a UKF's rank 1 waits in a collective with the dead rank 2: it owes its answer
// too).
void expectDeadRankLineAndResume(const std::string& section, bool keptOverRanks,
                                 const std::string& owing) {
  const auto dir = mpiSceneDir(section);
  const std::string run = "assimilate estimate.yaml --out out -q --no-plots --threads 1 --mpi";
  ASSERT_EQ(runBcassim(dir, "assimilate estimate.yaml --out t1 -q --no-plots --threads 1").exitCode,
            0);
  const test::CliResult killed = runMpiBcassim(dir, 3, run, "BCASSIM_TEST_MPI_KILL=2:4");
  EXPECT_NE(killed.exitCode, 0);
  const std::vector<std::string> lines = mpiLinesStartingWith(killed.err, "bcassim: error: ");
  ASSERT_EQ(lines.size(), 1u) << killed.err;
  EXPECT_EQ(
      lines[0],
      "bcassim: error: estimate.yaml: assimilation step 4: the MPI job was ended while " + owing +
          " had not answered (a rank died, or mpirun was stopped); the same command with --resume "
          "continues from the checkpoint of step 2")
      << killed.err;
  const test::CliResult resumed = runMpiBcassim(dir, 3, run + " --resume");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
  EXPECT_EQ(readText(dir / "out" / "estimates.csv"), readText(dir / "t1" / "estimates.csv"));
  EXPECT_LE(mpiCheckpointDifference(dir / "out", dir / "t1", keptOverRanks), 1e-12);
}

TEST(MpiExecutor, ADeadRankIsOneLineAndResumeFinishesTheRun) {
  expectDeadRankLineAndResume(kMpiRoukf, false, "rank 2");
}
TEST(MpiExecutor, ADeadRankDuringAUkfStepIsOneLineAndResumeFinishesTheRun) {
  expectDeadRankLineAndResume(kMpiUkf, true, "ranks 1, 2");
}

// A cantilever pulled by 10 N with a prior of 4,000 ± 3,500 Pa and star points (centre, ±): one
// sigma point per rank, and the one at the low modulus, on a worker, inverts an element even at
// time.min_dt. The worker answers the failure and serves the step again with the points pulled
// in: the same estimates and the same notice as the threaded run.
TEST(MpiExecutor, AForecastFailedOnAWorkerIsRedoneOnEveryRank) {
  const auto dir = freshDir();
  const std::string beam = test::pulledCantileverScene();
  writeText(dir / "truth.yaml", beam);
  writeText(dir / "estimate.yaml",
            beam +
                "assimilation:\n  sigma_points: star\n  reuse_factorization: false\n"
                "  parameters:\n    - {young_modulus: {region: 0}, mean: 4000, stddev: 3500}\n"
                "  observations: {tracks: truth/markers.csv}\n");
  ASSERT_EQ(runBcassim(dir, "simulate truth.yaml --out truth -q").exitCode, 0);
  const std::string run = "assimilate estimate.yaml -q --no-plots ";
  const test::CliResult alone = runBcassim(dir, run + "--out t1 --threads 1");
  ASSERT_EQ(alone.exitCode, 0) << alone.err;
  const test::CliResult three = runMpiBcassim(dir, 3, run + "--out m3 --threads 1 --mpi");
  ASSERT_EQ(three.exitCode, 0) << three.err;
  const std::string notices = readText(dir / "t1" / "notices.txt");
  EXPECT_NE(notices.find("the step's forecasts were redone with the sigma points at 1/2 of "
                         "their spread from the mean\n"),
            std::string::npos)
      << notices;
  // Rank 0 names the worker whose forecast failed; the rest of the line is the same.
  const std::string ranked = readText(dir / "m3" / "notices.txt");
  EXPECT_NE(ranked.find(": MPI rank "), std::string::npos) << ranked;
  EXPECT_EQ(std::count(ranked.begin(), ranked.end(), '\n'),
            std::count(notices.begin(), notices.end(), '\n'));
  EXPECT_EQ(readText(dir / "t1" / "estimates.csv"), readText(dir / "m3" / "estimates.csv"));
}

}  // namespace
}  // namespace bcassim
