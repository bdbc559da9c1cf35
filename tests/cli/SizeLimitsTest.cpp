// Scenes asking for what cannot be meant are refused at once, naming file, line and key: more
// markers than their region has nodes, generated meshes beyond mesh.max_nodes.
#include <gtest/gtest.h>

#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::expectSceneInputError;
using test::freshDir;
using test::runBcassim;
using test::writeText;

// The 4 x 1 x 1 box has 20 nodes, 4 of them at its free end (x = 0.1 m).
const std::string kBox = "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n";
const std::string kFreeEnd = "  - region: {box: {min: [0.0999, -1, -1], max: [1, 1, 1]}}\n";

TEST(SizeLimits, MoreMarkersThanTheRegionHasNodes) {
  expectSceneInputError(kBox + "markers:\n" + kFreeEnd + "    count: 1000\n",
                        "scene.yaml:4: markers[0].count: 1000 points asked, but the region has 4 "
                        "nodes; expected at most 4");
}

TEST(SizeLimits, MarkerCountBelowOne) {
  expectSceneInputError(kBox + "markers:\n" + kFreeEnd + "    count: 0\n",
                        "scene.yaml:4: markers[0].count: 0 points asked; expected at least 1");
}

TEST(SizeLimits, MoreValidationPointsThanTheRegionHasNodes) {
  expectSceneInputError(
      kBox +
          "validation_points:\n  region: {box: {min: [0.0999, -1, -1], max: [1, "
          "1, 1]}}\n  count: 5\n",
      "scene.yaml:4: validation_points.count: 5 points asked, but the region has 4 "
      "nodes; expected at most 4");
}

TEST(SizeLimits, CylinderBeyondMaxNodes) {
  expectSceneInputError("mesh: {generator: cylinder, target_nodes: 2000000000}\n",
                        "scene.yaml:1: mesh.target_nodes: 2000000000 nodes asked; expected at most "
                        "2000000 nodes (mesh.max_nodes)");
}

TEST(SizeLimits, BoxCellsBeyondMaxNodes) {
  // (1000 + 1)^3 nodes
  expectSceneInputError("mesh: {generator: box, cells: [1000, 1000, 1000]}\n",
                        "scene.yaml:1: mesh.cells: 1000 x 1000 x 1000 cells make 1003003001 nodes; "
                        "expected at most 2000000 nodes (mesh.max_nodes)");
}

TEST(SizeLimits, BoxTargetTetsBeyondMaxNodes) {
  // 6 tets per hexahedron: 1.2e9 tets need 2e8 hexahedra, each adding at least one node.
  expectSceneInputError("mesh: {generator: box, target_tets: 1200000000}\n",
                        "scene.yaml:1: mesh.target_tets: 1200000000 tets make at least 200000000 "
                        "nodes; expected at most 2000000 nodes (mesh.max_nodes)");
}

TEST(SizeLimits, MaxNodesIsAScenesOwnLimit) {
  // 5 x 2 x 2 = 20 nodes: refused under max_nodes 19, run under 20.
  const std::string box = "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1], ";
  expectSceneInputError(
      box + "max_nodes: 19}\n",
      "scene.yaml:1: mesh.cells: 4 x 1 x 1 cells make 20 nodes; expected at most 19 "
      "nodes (mesh.max_nodes)");
  const auto dir = freshDir();
  writeText(dir / "scene.yaml", box + "max_nodes: 20}\ntime: {steps: 1}\n");
  EXPECT_EQ(runBcassim(dir, "simulate scene.yaml --out out --quiet").exitCode, 0);
}

TEST(SizeLimits, MaxNodesOnlyForGenerators) {
  expectSceneInputError("mesh: {file: scene.yaml, max_nodes: 10}\n",
                        "scene.yaml:1: mesh.max_nodes: only for a generated mesh (mesh.generator)");
}

}  // namespace
}  // namespace bcassim
