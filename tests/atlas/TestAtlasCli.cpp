// `bcassim atlas` from the command line: the distance command and one-line errors naming the file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "atlas/AtlasTestMeshes.h"
#include "bcassim/atlas/FaceKernelDistance.h"
#include "bcassim/io/SurfaceReader.h"

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
  const CliRun noAtlas = runCli(dir, "atlas transfer nowhere a.obj");
  EXPECT_EQ(noAtlas.code, 2);
  EXPECT_NE(noAtlas.err.find("nowhere: expected an atlas folder"), std::string::npos)
      << noAtlas.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace bcassim
