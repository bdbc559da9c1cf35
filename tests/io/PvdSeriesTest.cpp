// PVD time series: files written per frame and an index that is complete after every frame.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "bcassim/io/MeshReader.h"
#include "bcassim/io/PvdSeries.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::cubeMesh;
using test::readText;
using test::TempDir;

TEST(PvdSeries, IndexListsEveryFrameAfterEachAddFrame) {
  TempDir dir;
  const std::string out = dir.file("run/output");
  PvdSeries series(out, "liver");
  const TetMesh mesh = cubeMesh();
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(
      Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>(mesh.V).data(), 24);
  for (int f = 0; f < 3; ++f) {
    const double t = 0.01 * f;
    x(2) = 0.1 * f;
    FieldSet fields;
    fields.pointScalars.emplace_back("index", Eigen::VectorXd::Constant(8, f));
    EXPECT_EQ(series.addFrame(t, mesh, x, fields), f);
    const std::string pvd = readText(series.pvdPath());
    EXPECT_NE(pvd.find("</VTKFile>"), std::string::npos);
    for (int g = 0; g <= f; ++g) {
      const std::string file = fmt::format("liver_{:06d}.vtu", g);
      EXPECT_NE(pvd.find(fmt::format("timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"", 0.01 * g,
                                     file)),
                std::string::npos)
          << pvd;
      EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + file));
    }
    EXPECT_EQ(readTetMesh(out + fmt::format("/liver_{:06d}.vtu", f)).V(0, 2), 0.1 * f);
  }
  EXPECT_EQ(series.numFrames(), 3);
  EXPECT_FALSE(std::filesystem::exists(series.pvdPath() + ".tmp"));
}

TEST(PvdSeries, ExtraPartsJoinTheLatestFrame) {
  TempDir dir;
  PvdSeries series(dir.path(), "run");
  series.addFrame(0.5, cubeMesh(), Eigen::VectorXd());
  series.addPoints("markers", Eigen::MatrixX3d::Zero(2, 3));
  Eigen::MatrixX2i segments(1, 2);
  segments << 0, 1;
  series.addPolyLines("springs", Eigen::MatrixX3d::Identity(2, 3), segments);
  const std::string pvd = readText(series.pvdPath());
  EXPECT_NE(pvd.find("timestep=\"0.5\" group=\"\" part=\"1\" file=\"run_markers_000000.vtp\""),
            std::string::npos)
      << pvd;
  EXPECT_NE(pvd.find("timestep=\"0.5\" group=\"\" part=\"2\" file=\"run_springs_000000.vtp\""),
            std::string::npos)
      << pvd;
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.file("run_markers_000000.vtp")));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.file("run_springs_000000.vtp")));
}

TEST(PvdSeries, DirectoryThatCannotBeCreated) {
  TempDir dir;
  const std::string file = test::writeText(dir.file("plain"), "x");
  const std::string message = test::inputErrorOf([&] { PvdSeries(file + "/sub", "run"); });
  EXPECT_EQ(message.rfind(file + "/sub: cannot create output directory", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace bcassim
