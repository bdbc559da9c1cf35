// Every bcassim command as --help shows it: the shared options (--out, --resume, -q, --threads)
// with one name and one wording wherever they appear, and argument errors as one line, exit 2.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::runBcassim;

// The help of SharedOptions.cpp, which every command shares.
const char* kOutHelp = "Output directory (created if missing)";
const char* kResumeHelp = "Continue a stopped run in --out from ";
const char* kQuietHelp = "No progress bars on stderr (results still printed)";
const char* kThreadsHelp = "Threads for ";

struct CommandOptions {
  std::string command;
  bool out, resume, quiet, threads;
};

// Which shared options each command has: --resume where a run can continue, -q where a progress
// bar is drawn, --threads where work runs in parallel (docs/architecture.md).
const std::vector<CommandOptions> kCommands = {
    {"simulate", true, true, true, false},           {"assimilate", true, true, true, true},
    {"validate", true, false, true, false},          {"mesh info", false, false, false, false},
    {"mesh tetra", true, false, false, false},       {"atlas distance", false, false, false, true},
    {"atlas register", true, false, false, true},    {"atlas build", true, false, false, true},
    {"atlas transfer", true, false, false, true},    {"atlas loo", true, false, false, true},
    {"liver prepare", true, false, false, true},     {"liver run", true, true, true, true},
    {"liver tracked", true, true, true, true},       {"track", true, false, false, false},
    {"register", true, false, false, false},         {"ligament fit", true, false, false, false},
    {"ligament springs", true, false, false, false},
};

using test::contains;

TEST(CommandOptions, EveryHelpListsTheSharedOptionsWithOneWording) {
  const auto dir = freshDir();
  for (const CommandOptions& c : kCommands) {
    SCOPED_TRACE(c.command);
    const test::CliResult r = runBcassim(dir, c.command + " --help");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(contains(r.out, "-o,--out"), c.out) << r.out;
    EXPECT_EQ(contains(r.out, kOutHelp), c.out) << r.out;
    EXPECT_EQ(contains(r.out, "--resume"), c.resume) << r.out;
    EXPECT_EQ(contains(r.out, kResumeHelp), c.resume) << r.out;
    EXPECT_EQ(contains(r.out, "-q,--quiet"), c.quiet) << r.out;
    EXPECT_EQ(contains(r.out, kQuietHelp), c.quiet) << r.out;
    EXPECT_EQ(contains(r.out, "--threads"), c.threads) << r.out;
    EXPECT_EQ(contains(r.out, kThreadsHelp), c.threads) << r.out;
  }
}

TEST(CommandOptions, OutShowsItsDefault) {
  const auto dir = freshDir();
  EXPECT_TRUE(contains(runBcassim(dir, "simulate --help").out, "-o,--out TEXT=out "));
  EXPECT_TRUE(contains(runBcassim(dir, "liver run --help").out, "-o,--out TEXT=out/liver "));
  EXPECT_TRUE(contains(runBcassim(dir, "atlas build --help").out, "-o,--out TEXT=out/atlas "));
  EXPECT_TRUE(contains(runBcassim(dir, "track --help").out, "-o,--out TEXT=out/track "));
  EXPECT_TRUE(contains(runBcassim(dir, "register --help").out, "-o,--out TEXT=out/register "));
  EXPECT_TRUE(
      contains(runBcassim(dir, "liver tracked --help").out, "-o,--out TEXT=out/liver-tracked\n"));
}

TEST(CommandOptions, TopLevelHelpListsEveryGroup) {
  const auto dir = freshDir();
  const test::CliResult r = runBcassim(dir, "--help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* name : {"simulate", "assimilate", "validate", "mesh", "track", "register",
                           "atlas", "liver", "ligament"})
    EXPECT_TRUE(contains(r.out, name)) << name;
}

TEST(CommandOptions, UnknownOptionIsOneLineAndExit2) {
  const auto dir = freshDir();
  for (const char* command : {"simulate scene.yaml", "atlas build livers", "liver run phantom",
                              "track d.csv", "register m.vtu p.csv", "liver tracked phantom"}) {
    SCOPED_TRACE(command);
    const test::CliResult r = runBcassim(dir, std::string(command) + " --no-such-option");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::countLines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("bcassim: error: ", 0), 0u) << r.err;
    EXPECT_TRUE(contains(r.err, "--no-such-option")) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

TEST(CommandOptions, LigamentFitRefusesACurveInMegapascalOrANegativeStretchInOneLine) {
  const auto dir = freshDir();
  std::ofstream(dir / "mpa.csv") << "strain,nominal_stress_MPa\n0,0\n0.1,0.01\n";
  std::ofstream(dir / "negative.csv") << "stretch,cauchy_stress_Pa\n1,0\n-0.2,100\n";
  const test::CliResult mpa = runBcassim(dir, "ligament fit mpa.csv");
  EXPECT_EQ(mpa.exitCode, 2);
  EXPECT_EQ(mpa.err,
            "bcassim: error: mpa.csv:1: column nominal_stress_MPa: stress in MPa; expected Pa "
            "(SI units), e.g. nominal_stress_Pa\n");
  const test::CliResult negative = runBcassim(dir, "ligament fit negative.csv --model ogden");
  EXPECT_EQ(negative.exitCode, 2);
  EXPECT_EQ(negative.err,
            "bcassim: error: negative.csv:3: stretch -0.2: expected a stretch > 0 (a strain > "
            "-1)\n");
  const test::CliResult bound = runBcassim(dir, "ligament fit mpa.csv --bound alpha");
  EXPECT_EQ(bound.err,
            "bcassim: error: --bound 'alpha': expected NAME=LOWER:UPPER, e.g. alpha=1:30\n");
}

TEST(CommandOptions, GroupWithoutCommandIsOneLineAndExit2) {
  const auto dir = freshDir();
  for (const char* group : {"mesh", "atlas", "liver", "ligament"}) {
    const test::CliResult r = runBcassim(dir, group);
    EXPECT_EQ(r.exitCode, 2) << group;
    EXPECT_EQ(test::countLines(r.err), 1) << r.err;
  }
}

// The value of --threads: the one line naming it, exit 2.
void expectThreadsRefused(const std::string& command, const std::string& value) {
  for (const char* separator : {"=", " "}) {
    const std::string args = command + " --threads" + separator + value;
    SCOPED_TRACE(args);
    const test::CliResult r = runBcassim(freshDir(), args);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, "bcassim: error: --threads: expected a whole number of threads >= 1, got '" +
                         value + "' (see 'bcassim --help')\n");
    EXPECT_EQ(r.out, "");
  }
}

TEST(CommandOptions, ThreadsBelowOneIsAnArgumentErrorNamingThreads) {
  for (const char* value : {"0", "-2", "two", "1.5"})
    expectThreadsRefused("assimilate s.yaml", value);
  for (const char* command : {"liver run phantom", "liver prepare phantom", "liver tracked phantom",
                              "atlas build livers", "atlas distance a.obj b.obj"})
    expectThreadsRefused(command, "0");
}

TEST(CommandOptions, NegativeWalkAndCameraOffsetAreArgumentErrorsNamingTheOption) {
  const std::pair<const char*, const char*> options[] = {
      {"liver prepare phantom", "--stiffness-walk"},
      {"liver prepare phantom", "--prior-spread"},
      {"liver tracked phantom", "--camera-offset"},
      {"serve s.yaml", "--idle-timeout"},
      {"serve s.yaml", "--filter-delay"},
      {"replay t.csv --to h:1", "--wait"}};
  for (const auto& [command, option] : options)
    for (const char* value : {"-0.5", "x", "nan"}) {
      const std::string args = std::string(command) + " " + option + "=" + value;
      SCOPED_TRACE(args);
      const test::CliResult r = runBcassim(freshDir(), args);
      EXPECT_EQ(r.exitCode, 2);
      EXPECT_EQ(r.err, std::string("bcassim: error: ") + option +
                           ": expected a number >= 0, got '" + value +
                           "' (see 'bcassim --help')\n");
      EXPECT_EQ(r.out, "");
    }
}

// liver tracked's point-cloud variant: what the camera gives and its sizes, out of range: one
// line naming the option, exit 2, before anything runs; the help gives each default.
TEST(CommandOptions, LiverTrackedSurfaceOptionsRefuseBadValuesNamingTheOption) {
  const auto dir = freshDir();
  const std::pair<const char*, const char*> refused[] = {
      {"--observe points", "--observe: points not in {tackers,surface}"},
      {"--surface-coverage 2", "--surface-coverage: Value 2 not in range 0.010000 to 1.000000"},
      {"--surface-points 5", "--surface-points: Value 5 not in range 10 to 1000000"},
      {"--surface-outliers 0.7", "--surface-outliers: Value 0.7 not in range 0.000000 to 0.500000"},
      {"--surface-relinearizations -1",
       "--surface-relinearizations: Value -1 not in range 0 to 100"}};
  for (const auto& [option, message] : refused) {
    SCOPED_TRACE(option);
    const test::CliResult r = runBcassim(dir, std::string("liver tracked phantom ") + option);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err, std::string("bcassim: error: ") + message + " (see 'bcassim --help')\n");
    EXPECT_EQ(r.out, "");
  }
  const std::string help = runBcassim(dir, "liver tracked --help").out;
  for (const char* line : {"--observe TEXT:{tackers,surface}=tackers",
                           "--surface-coverage FLOAT:FLOAT in [0.01 - 1]=0.3",
                           "--surface-points INT:INT in [10 - 1000000]=500",
                           "--surface-outliers FLOAT:FLOAT in [0 - 0.5]=0.01",
                           "--surface-relinearizations INT:INT in [0 - 100]=0"})
    EXPECT_TRUE(contains(help, line)) << line;
}

// serve and replay: a time offset that is no number, an address that is not HOST:PORT, a port,
// rate or lag out of range: one line naming the option, exit 2, before any file is read.
TEST(CommandOptions, ServeAndReplayRefuseBadValuesNamingTheOption) {
  const auto dir = freshDir();
  test::CliResult r = runBcassim(dir, "serve missing.yaml --time-offset soon");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err,
            "bcassim: error: --time-offset 'soon': expected 'scene', 'first' or a number of "
            "seconds\n");
  // The tracks are read first, so write some.
  test::writeText(dir / "t.csv", "time,marker,x,y,z\n0.02,0,0,0,0\n");
  for (const char* to : {"localhost", "h:0", "h:70000", ":18944", "h:18944x"}) {
    r = runBcassim(dir, std::string("replay t.csv --to ") + to);
    EXPECT_EQ(r.exitCode, 2) << to;
    EXPECT_EQ(r.err, std::string("bcassim: error: --to '") + to +
                         "': expected HOST:PORT with a port from 1 to 65535\n");
  }
  for (const char* args :
       {"serve s.yaml --port 70000", "serve s.yaml --max-lag 0",
        "serve s.yaml --real-time-step fast", "replay t.csv --to h:1 --rate 0"}) {
    r = runBcassim(dir, args);
    const std::string option = std::string(args).substr(std::string(args).rfind(" --") + 1);
    EXPECT_EQ(r.exitCode, 2) << args;
    EXPECT_EQ(test::countLines(r.err), 1) << r.err;
    EXPECT_TRUE(contains(r.err, option.substr(0, option.find(' ')))) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

// A file that is not there: the command's one-line message naming it, exit 2, nothing on stdout.
void expectMissingFile(const std::string& args, const std::string& message) {
  SCOPED_TRACE(args);
  const test::CliResult r = runBcassim(freshDir(), args);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: " + message + "\n");
  EXPECT_EQ(r.out, "");
}

TEST(CommandOptions, MissingInputFileIsOneLineNamingIt) {
  expectMissingFile("assimilate none.yaml", "none.yaml: cannot open file");
  expectMissingFile("validate none.yaml --estimates e.csv", "none.yaml: cannot open file");
  const char* noSurface = ": no such file (expected a triangle surface .obj/.stl/.ply/.vtk/.vtp)";
  expectMissingFile("atlas distance none.obj b.obj", std::string("none.obj") + noSurface);
  expectMissingFile("atlas register none.obj b.obj --out o", std::string("none.obj") + noSurface);
  expectMissingFile("track none.csv", "none.csv: cannot open file");
  expectMissingFile("register none.vtu p.csv", "none.vtu: cannot open file");
  // liver prepare names the surface on stdout first; then the one line of the file it lacks.
  const std::pair<const char*, const char*> liverFiles[] = {
      {"--spring-priors none.yaml", "none.yaml: cannot read the spring priors (springs.yaml)"},
      {"--atlas none", "none: expected an atlas folder (from 'bcassim atlas build')"}};
  for (const auto& [option, message] : liverFiles) {
    const test::CliResult r =
        runBcassim(freshDir(), std::string("liver prepare phantom ") + option);
    EXPECT_EQ(r.exitCode, 2) << option;
    EXPECT_EQ(r.err, std::string("bcassim: error: ") + message + "\n");
  }
}

TEST(CommandOptions, AtlasBandWithoutAnAtlasIsOneLine) {
  const test::CliResult r = runBcassim(freshDir(), "liver prepare phantom --atlas-band");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err,
            "bcassim: error: liver: --atlas-band spreads the springs over an atlas' band; it "
            "needs --atlas (or --atlas-livers)\n");
}

}  // namespace
}  // namespace bcassim
