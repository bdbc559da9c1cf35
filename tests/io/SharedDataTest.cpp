// The real data files of ../shared/data, when present: counts that the other modules rely on.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "bcassim/io/MeshReader.h"
#include "bcassim/io/SurfaceReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

TEST(SharedData, OptimusCylinder) {
  SHARED_FILE_OR_SKIP(path, "optimus-cylinder/cylinder3_770.vtk");
  const TetMesh mesh = readTetMesh(path);
  EXPECT_EQ(mesh.numNodes(), 208);
  EXPECT_EQ(mesh.numTets(), 770);
  const std::set<int> regions(mesh.region.begin(), mesh.region.end());
  EXPECT_EQ(regions, (std::set<int>{1, 2, 3}));
  EXPECT_NEAR(mesh.V.col(2).maxCoeff(), 0.24, 1e-7);  // stored as float
}

TEST(SharedData, OptimusObservedPoints) {
  SHARED_FILE_OR_SKIP(path, "optimus-cylinder/cyl10_4245_obs33.vtk");
  const Eigen::MatrixX3d points = readPoints(path);
  EXPECT_EQ(points.rows(), 33);
  EXPECT_NEAR(points(0, 0), 0.02, 1e-7);
  EXPECT_NEAR(points(0, 2), 0.08, 1e-7);
}

TEST(SharedData, SofaLiverGmshVersion1) {
  SHARED_FILE_OR_SKIP(coarse, "sofa-liver/liver.msh");
  EXPECT_EQ(readTetMesh(coarse).numTets(), 596);
  SHARED_FILE_OR_SKIP(path, "sofa-liver/liver2.msh");
  const TetMesh mesh = readTetMesh(path);
  EXPECT_EQ(mesh.numNodes(), 507);
  EXPECT_EQ(mesh.numTets(), 1493);
}

TEST(SharedData, SofaLiverFineVtu) {
  SHARED_FILE_OR_SKIP(path, "sofa-liver/liverFine.vtu");
  const TetMesh mesh = readTetMesh(path);
  EXPECT_EQ(mesh.numNodes(), 4293);
  EXPECT_EQ(mesh.numTets(), 22019);
}

TEST(SharedData, SofaLiverSurfaces) {
  SHARED_FILE_OR_SKIP(obj, "sofa-liver/liver-smooth.obj");
  const TriMesh smooth = readSurface(obj);
  EXPECT_EQ(smooth.V.rows(), 2194);
  SHARED_FILE_OR_SKIP(vtk, "sofa-liver/liver.vtk");
  EXPECT_EQ(readSurface(vtk).V.rows(), 5008);
}

TEST(SharedData, PatientLiverObj) {
  SHARED_FILE_OR_SKIP(path, "livers/LiTS-0.obj");
  const TriMesh mesh = readSurface(path);
  EXPECT_GT(mesh.V.rows(), 1000);
  EXPECT_EQ(mesh.F.rows(), 3800);
  EXPECT_GE(mesh.F.minCoeff(), 0);
  EXPECT_LT(mesh.F.maxCoeff(), mesh.V.rows());
}

}  // namespace
}  // namespace bcassim
