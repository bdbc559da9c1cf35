// Tests of SurfaceMesher: repair of a broken synthetic sphere, and meshing of a real CT liver.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>

#include "bcassim/Error.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/ligaments/SurfaceMesher.h"
#include "bcassim/mesh/MeshQuality.h"
#include "bcassim/mesh/MeshValidation.h"
#include "ligaments/LigamentTestData.h"

namespace bcassim {
namespace {

TEST(SurfaceMesher, RepairsDuplicatedVertexAndMissingFaceOfSphere) {
  TriMesh sphere = test::makeIcosphere(0.05, 3);  // 1,280 faces, metres
  // Face 0 gets its own copy of its first vertex (a duplicated point), and the last face is lost.
  const int copied = sphere.F(0, 0);
  sphere.V.conservativeResize(sphere.V.rows() + 1, 3);
  sphere.V.row(sphere.V.rows() - 1) = sphere.V.row(copied);
  sphere.F(0, 0) = static_cast<int>(sphere.V.rows() - 1);
  sphere.F.conservativeResize(sphere.F.rows() - 1, 3);

  SurfaceMeshingOptions options;
  options.scale = 1.0;
  options.targetNodes = 400;
  const SurfaceMeshingResult result = meshSurface(sphere, options, "sphere");
  EXPECT_EQ(result.report.mergedVertices, 1);
  EXPECT_EQ(result.report.holesFilled, 1);
  EXPECT_EQ(result.report.components, 1);
  EXPECT_EQ(result.report.genus, 0);
  EXPECT_EQ(result.report.selfIntersections, 0);
  const double exact = 4.0 / 3.0 * std::numbers::pi * std::pow(0.05, 3);
  EXPECT_NEAR(result.report.surfaceVolume, exact, 0.02 * exact);
  EXPECT_NEAR(result.report.meshVolume, exact, 0.05 * exact);
  const MeshQuality quality = measureQuality(result.mesh);
  EXPECT_EQ(quality.numInverted, 0);
  EXPECT_NEAR(result.mesh.numNodes(), 400, 0.2 * 400);
  EXPECT_GT(quality.minDihedralDeg, 0.1);  // no exudation: slivers remain (0.64 deg seen)
}

TEST(SurfaceMesher, InwardSurfaceIsReorientedAndScaled) {
  TriMesh sphere = test::makeIcosphere(50.0, 2);  // millimetres, faces turned inward
  sphere.F.col(1).swap(sphere.F.col(2));
  SurfaceMeshingOptions options;  // scale 1e-3
  options.targetNodes = 200;
  const SurfaceMeshingResult result = meshSurface(sphere, options, "inward");
  EXPECT_EQ(result.report.flippedFaces, sphere.F.rows());
  EXPECT_GT(result.report.surfaceVolume, 0);
  EXPECT_NEAR(result.mesh.V.col(0).maxCoeff(), 0.05, 0.002);
  EXPECT_EQ(measureQuality(result.mesh).numInverted, 0);
}

TEST(SurfaceMesher, IsDeterministic) {
  const TriMesh sphere = test::makeIcosphere(0.05, 2);
  SurfaceMeshingOptions options;
  options.scale = 1.0;
  options.targetNodes = 200;
  const TetMesh a = meshSurface(sphere, options).mesh, b = meshSurface(sphere, options).mesh;
  ASSERT_EQ(a.numNodes(), b.numNodes());
  ASSERT_EQ(a.numTets(), b.numTets());
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.T, b.T);
}

TEST(SurfaceMesher, OversizedHoleIsAnInputError) {
  TriMesh sphere = test::makeIcosphere(0.05, 2);
  sphere.F.conservativeResize(sphere.F.rows() / 2, 3);  // half a sphere: one big border loop
  SurfaceMeshingOptions options;
  options.scale = 1.0;
  options.maxHoleEdges = 10;
  try {
    meshSurface(sphere, options, "half.obj");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("half.obj: a border loop of"), std::string::npos)
        << e.what();
  }
}

TEST(SurfaceMesher, MeshesCoarseCtLiverInMetres) {
  const std::string data = test::ligamentDataDir();
  if (data.empty()) GTEST_SKIP() << "shared data directory not found (set BCASSIM_DATA)";
  const TriMesh liver = readObj(data + "/livers/LiTS-0.obj");
  SurfaceMeshingOptions options;
  options.targetNodes = 800;
  SurfaceMeshingResult result = meshSurface(liver, options, "LiTS-0.obj");
  validateTetMesh(result.mesh, "LiTS-0");
  const MeshQuality quality = measureQuality(result.mesh);
  EXPECT_EQ(quality.numInverted, 0);
  EXPECT_NEAR(quality.numNodes, 800, 0.2 * 800);
  EXPECT_NEAR(quality.totalVolume, result.report.surfaceVolume, 0.05 * result.report.surfaceVolume);
  const double width = (quality.bboxMax - quality.bboxMin).maxCoeff();
  EXPECT_GT(width, 0.1);
  EXPECT_LT(width, 0.3);
}

// The batch over all livers takes a few minutes: run it with BCASSIM_MESH_ALL=<report.md>.
TEST(SurfaceMesher, BatchReportOnAllLivers) {
  const char* out = std::getenv("BCASSIM_MESH_ALL");
  const std::string data = test::ligamentDataDir();
  if (!out || data.empty()) GTEST_SKIP() << "set BCASSIM_MESH_ALL=<report.md> to run the batch";
  SurfaceMeshingOptions options;
  if (const char* target = std::getenv("BCASSIM_MESH_TARGET"))
    options.targetNodes = std::atoi(target);
  const auto outcomes = meshAllLivers(data, options);
  std::ofstream md(out);
  md << "| file | ok | in V/F | nodes | tets | min dihedral | vol ratio | s | notes |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (const LiverMeshingOutcome& o : outcomes) {
    const SurfaceMeshingReport& r = o.report;
    md << "| " << o.file << " | " << (o.ok ? "yes" : "**no**") << " | " << r.inputVertices << "/"
       << r.inputFaces << " | " << r.outputNodes << " | " << r.outputTets << " | "
       << r.minDihedralDeg << " | " << (r.surfaceVolume > 0 ? r.meshVolume / r.surfaceVolume : 0)
       << " | " << r.seconds << " | " << o.problem << " |\n";
  }
  EXPECT_FALSE(outcomes.empty());
}

}  // namespace
}  // namespace bcassim
