// `bcassim atlas` from the command line: the distance command and one-line errors naming the file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/atlas/FaceKernelDistance.h"
#include "bcassim/io/SurfaceReader.h"
#include "support/SharedData.h"

namespace bcassim {
namespace {
namespace fs = std::filesystem;

struct CliRun {
  int code;
  std::string out, err;
};

CliRun runCli(const fs::path& dir, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.string() + "' && '" + BCASSIM_BINARY + "' " + args + " > cli.out 2> cli.err";
  const int status = std::system(cmd.c_str());
  auto slurp = [&](const char* name) {
    std::ifstream f(dir / name);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp("cli.out"), slurp("cli.err")};
}

TEST(AtlasCli, DistancePrintsTheVarifoldDistanceAndBadInputIsOneLine) {
  if (!fs::exists(BCASSIM_BINARY)) GTEST_SKIP() << "bcassim not built";
  const fs::path dir = fs::temp_directory_path() / "bcassim-test-atlas-cli";
  fs::create_directories(dir);
  const TriMesh a = test::makeIcosphere(50.0, 2);  // mm, as the shared livers
  TriMesh b = a;
  b.V.col(0) *= 1.1;
  writeSurface((dir / "a.obj").string(), a);
  writeSurface((dir / "b.obj").string(), b);
  const CliRun same = runCli(dir, "atlas distance a.obj a.obj --sigma 0.01");
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_NEAR(std::stod(same.out), 0.0, 1e-15);
  const CliRun diff = runCli(dir, "atlas distance a.obj b.obj --sigma 0.01 --kernel current");
  ASSERT_EQ(diff.code, 0) << diff.err;
  TriMesh am = a, bm = b;
  am.V *= 1e-3;  // --scale defaults to 1e-3 (mm files)
  bm.V *= 1e-3;
  const double expected = FaceKernelDistance(bm, 0.01, FaceKernelKind::Current).value(am.V, am.F);
  EXPECT_NEAR(std::stod(diff.out), expected, 1e-8 * expected);
  // --threads caps the kernel sums' threads; each row is summed whole by one and the rows in order.
  const CliRun oneThread =
      runCli(dir, "atlas distance a.obj b.obj --sigma 0.01 --kernel current --threads 1");
  ASSERT_EQ(oneThread.code, 0) << oneThread.err;
  EXPECT_EQ(oneThread.out, diff.out);
  const CliRun bad = runCli(dir, "atlas distance a.obj missing.obj");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("missing.obj"), std::string::npos) << bad.err;
  EXPECT_EQ(bad.err.find('\n'), bad.err.size() - 1) << bad.err;  // one line
  // The ridge options' bad values: one line each, before any work.
  const CliRun negative = runCli(dir, "atlas build . --ridge --ridge-weight -1");
  EXPECT_EQ(negative.code, 2);
  EXPECT_NE(negative.err.find("--ridge-weight"), std::string::npos) << negative.err;
  EXPECT_EQ(negative.err.find('\n'), negative.err.size() - 1) << negative.err;
  const CliRun alone = runCli(dir, "atlas loo . --ridge-on-held-out");
  EXPECT_EQ(alone.code, 2);
  EXPECT_EQ(alone.err, "bcassim: error: --ridge-on-held-out: needs --ridge\n");
  const CliRun none = runCli(dir, "atlas loo . --nearest 5,0");
  EXPECT_EQ(none.code, 2);
  EXPECT_EQ(none.err, "bcassim: error: --nearest 0: expected a count >= 1\n");
  // A fusion template that is not one of the livers, or is the template itself.
  const std::string livers = (fs::path(test::sharedDataDir()) / "livers").string();
  for (const std::string name : {"nowhere", "3Dircadb-10"}) {
    const CliRun fuse = runCli(dir, "atlas loo '" + livers + "' --max-livers 3 --fuse-templates " +
                                        name + " --template 3Dircadb-10");
    EXPECT_EQ(fuse.code, 2);
    EXPECT_EQ(fuse.err, "bcassim: error: --fuse-templates " + name +
                            ": expected the name of a usable liver of " + livers +
                            " other than the template\n");
  }
  const CliRun twice = runCli(dir, "atlas loo '" + livers +
                                       "' --max-livers 3 --fuse-templates 3Dircadb-11,3Dircadb-11 "
                                       "--template 3Dircadb-10");
  EXPECT_EQ(twice.code, 2);
  EXPECT_EQ(
      twice.err,
      "bcassim: error: --fuse-templates 3Dircadb-11: named twice; expected each liver once\n");
  const CliRun noAtlas = runCli(dir, "atlas transfer nowhere a.obj");
  EXPECT_EQ(noAtlas.code, 2);
  EXPECT_NE(noAtlas.err.find("nowhere: expected an atlas folder"), std::string::npos)
      << noAtlas.err;
  fs::remove_all(dir);
}

// Numbers of a CSV file's data lines (header skipped).
std::vector<std::vector<double>> csvNumbers(const fs::path& path) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(f, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string field; std::getline(ss, field, ',');) row.push_back(std::stod(field));
    rows.push_back(row);
  }
  return rows;
}

const fs::path kLivers = fs::path(test::sharedDataDir()) / "livers";

// In a fresh dir: an atlas of the first three shared livers (dir/atlas, with its template's
// ridge), then `atlas transfer` of it onto `liver` compared with its .eseg (dir/transfer).
CliRun transferOfASmallAtlas(const fs::path& dir, const std::string& liver,
                             const std::string& more = "") {
  fs::remove_all(dir);
  fs::create_directories(dir);
  const CliRun build = runCli(dir, "atlas build '" + kLivers.string() +
                                       "' --max-livers 3 --no-frechet --iterations 5 --out atlas");
  EXPECT_EQ(build.code, 0) << build.err;
  return runCli(dir, "atlas transfer atlas '" + (kLivers / (liver + ".obj")).string() +
                         "' --eseg '" + (kLivers / (liver + ".eseg")).string() +
                         "' --iterations 5 --out transfer " + more);
}

TEST(AtlasCli, TransferWritesTheRigidTransformAndTheCurveInTheFileUnits) {
  SHARED_FILE_OR_SKIP(eseg, "livers/LiTS-3.eseg");
  const fs::path dir = fs::temp_directory_path() / "bcassim_atlas_cli_transfer";
  const CliRun transfer = transferOfASmallAtlas(dir, "LiTS-3");
  ASSERT_EQ(transfer.code, 0) << transfer.err;
  EXPECT_NE(transfer.out.find("distance to the expert curve: planes "), std::string::npos);
  EXPECT_NE(transfer.out.find("distance to the expert's whole band ("), std::string::npos);
  const auto metres = csvNumbers(dir / "transfer/ligament_curve.csv");
  const auto fileUnits = csvNumbers(dir / "transfer/ligament_curve_file_units.csv");
  ASSERT_EQ(metres.size(), fileUnits.size());
  ASSERT_FALSE(metres.empty());
  for (size_t i = 0; i < metres.size(); ++i)
    for (size_t c = 0; c < 4; ++c)  // x, y, z, sigma: the livers are in mm
      EXPECT_NEAR(fileUnits[i][c], 1e3 * metres[i][c], 1e-9 * std::abs(1e3 * metres[i][c]) + 1e-12);
  const auto rigid = csvNumbers(dir / "transfer/rigid_transform.csv");
  ASSERT_EQ(rigid.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {  // a rotation: R R^T = I
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += rigid[i][1 + k] * rigid[j][1 + k];
      EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12);
    }
    EXPECT_NEAR(rigid[i][5], 1e3 * rigid[i][4], 1e-9);
  }
  // The patient's ridge matched with the atlas template's (multi-object data term).
  const CliRun ridged =
      runCli(dir, "atlas transfer atlas '" + (kLivers / "LiTS-3.obj").string() +
                      "' --ridge-from '" + eseg + "' --iterations 5 --out ridged");
  ASSERT_EQ(ridged.code, 0) << ridged.err;
  EXPECT_TRUE(fs::exists(dir / "ridged/ligament_curve.csv"));
  // A .eseg that labels no ridge: one line naming it.
  {
    std::ifstream in(eseg);
    std::ofstream out(dir / "no-ridge.eseg");
    for (std::string line; std::getline(in, line);) {  // the shared files end lines with \r\n
      if (!line.empty() && line.back() == '\r') line.pop_back();
      out << (line == "3" ? "1" : line) << '\n';
    }
  }
  const CliRun noRidge = runCli(dir, "atlas transfer atlas '" + (kLivers / "LiTS-3.obj").string() +
                                         "' --ridge-from no-ridge.eseg --out none");
  EXPECT_EQ(noRidge.code, 2);
  EXPECT_EQ(noRidge.err, "bcassim: error: no-ridge.eseg: no edge carries label 3 (the ridge)\n");
  fs::remove_all(dir);
}

// LiTS-9 onto an atlas of three livers: two poses 54 deg apart fit it alike (RMS 9.3 mm each),
// one puts the transferred curve 27 mm from the expert's, the other 93 mm. The surfaces cannot
// tell them apart; the run must say so (and keep the multi-start's pose, the right one here).
// The patient's ridge, when labelled, can: fitted with the surfaces, no rival is left.
TEST(AtlasCli, TransferSaysWhenTwoPosesFitAlike) {
  SHARED_FILE_OR_SKIP(eseg, "livers/LiTS-9.eseg");
  const fs::path dir = fs::temp_directory_path() / "bcassim_atlas_cli_pose";
  const CliRun transfer = transferOfASmallAtlas(dir, "LiTS-9");
  ASSERT_EQ(transfer.code, 0) << transfer.err;
  EXPECT_NE(transfer.out.find("ambiguous pose: a rival rigid fit "), std::string::npos)
      << transfer.out;
  const auto at = transfer.out.find("distance to the expert curve: planes ");
  ASSERT_NE(at, std::string::npos) << transfer.out;
  const std::string rest = transfer.out.substr(at);
  const double mean = std::stod(rest.substr(rest.find(" mean ") + 6));
  EXPECT_LT(mean, 40.0) << rest;  // mm; the rival pose: 93 mm
  const CliRun ridged =
      runCli(dir, "atlas transfer atlas '" + (kLivers / "LiTS-9.obj").string() + "' --eseg '" +
                      eseg + "' --ridge-from '" + eseg + "' --iterations 5 --out ridged");
  ASSERT_EQ(ridged.code, 0) << ridged.err;
  EXPECT_NE(ridged.out.find("mm (surface and ridge together, the ridge's closest 80 %)\n"),
            std::string::npos)
      << ridged.out;
  EXPECT_EQ(ridged.out.find("ambiguous pose"), std::string::npos) << ridged.out;
  const auto atRidged = ridged.out.find("distance to the expert curve: planes ");
  ASSERT_NE(atRidged, std::string::npos) << ridged.out;
  const std::string restRidged = ridged.out.substr(atRidged);
  EXPECT_LT(std::stod(restRidged.substr(restRidged.find(" mean ") + 6)), 40.0) << restRidged;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace bcassim
