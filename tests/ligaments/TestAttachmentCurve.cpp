// Tests of .eseg reading and attachment-curve extraction on a synthetic labelled grid.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "bcassim/Error.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/ligaments/AttachmentCurve.h"
#include "bcassim/ligaments/EsegLabels.h"

namespace bcassim {
namespace {

// n x n vertex grid in the z = 0 plane, spacing 1, vertex (i, j) = i + n j, two triangles a cell.
TriMesh makeGrid(int n) {
  TriMesh grid;
  grid.V.resize(n * n, 3);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) grid.V.row(i + n * j) << i, j, 0;
  }
  grid.F.resize(2 * (n - 1) * (n - 1), 3);
  int f = 0;
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = i + n * j, b = a + 1, c = a + n, d = c + 1;
      grid.F.row(f++) << a, b, d;
      grid.F.row(f++) << a, d, c;
    }
  }
  return grid;
}

// Writes `surface` and an .eseg labelling with 2 the edges between consecutive vertices of each
// path in `paths`; returns the .eseg path.
std::string writeLabelled(const std::string& name, const TriMesh& surface,
                          const std::vector<std::vector<int>>& paths) {
  const std::string dir = (std::filesystem::temp_directory_path() / "bcassim-ligaments").string();
  std::filesystem::create_directories(dir);
  writeObj(dir + "/" + name + ".obj", surface);
  std::set<std::pair<int, int>> labelled;
  for (const auto& path : paths) {
    for (size_t i = 1; i < path.size(); ++i) labelled.insert(std::minmax(path[i - 1], path[i]));
  }
  std::ofstream out(dir + "/" + name + ".eseg");
  for (const auto& [a, b] : esegEdgeOrder(surface)) {
    out << (labelled.count(std::minmax(a, b)) ? 2 : 1) << "\r\n";  // the data files use CRLF
  }
  return dir + "/" + name + ".eseg";
}

TEST(EsegLabels, EdgeOrderFollowsFacesThenCorners) {
  TriMesh two;
  two.V = Eigen::MatrixX3d::Zero(4, 3);
  two.F.resize(2, 3);
  two.F << 0, 1, 2, 2, 1, 3;
  const auto edges = esegEdgeOrder(two);
  const std::vector<std::array<int, 2>> expected = {{0, 1}, {1, 2}, {2, 0}, {1, 3}, {3, 2}};
  EXPECT_EQ(edges, expected);
}

TEST(EsegLabels, WrongLabelCountIsAOneLineError) {
  const TriMesh grid = makeGrid(4);  // 9 cells: 33 edges
  const std::string path = writeLabelled("short", grid, {});
  {
    std::ofstream out(path);
    for (int e = 0; e < 32; ++e) out << "1\n";
  }
  try {
    readEseg(path, grid);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ":33: expected 33 edge labels (one per surface edge), the file ends after 32");
  }
  {
    std::ofstream out(path);
    for (int e = 0; e < 34; ++e) out << "1\n";
  }
  try {
    readEseg(path, grid);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ":34: expected 33 edge labels (one per surface edge), the file has more");
  }
  {
    std::ofstream out(path);
    out << "1\nx2\n";
  }
  EXPECT_THROW(readEseg(path, grid), InputError);
}

TEST(AttachmentCurve, OrderedCurveEqualsLabelledPath) {
  const TriMesh grid = makeGrid(6);
  // A staircase through the grid using horizontal, vertical and diagonal edges.
  const std::vector<int> path = {0, 1, 8, 9, 15, 21, 22, 29, 35};
  const std::string eseg = writeLabelled("path", grid, {path});
  const TriMesh surface = readObj(eseg.substr(0, eseg.size() - 5) + ".obj");
  const AttachmentCurve curve = extractAttachmentCurve(surface, readEseg(eseg, surface), 2);
  EXPECT_EQ(curve.vertices, path);  // starts at the end with the smaller id
  EXPECT_EQ(curve.components, 1);
  EXPECT_EQ(curve.droppedVertices, 0);
  EXPECT_NEAR(curve.length, 6 + 2 * std::sqrt(2.0), 1e-12);
  EXPECT_EQ(curve.points.row(3), surface.V.row(9));
}

TEST(AttachmentCurve, DropsSideBranchAndJoinsGap) {
  const TriMesh grid = makeGrid(8);
  const std::vector<int> first = {0, 1, 2, 3};  // along the bottom row
  const std::vector<int> branch = {2, 10};      // a stray edge upward
  const std::vector<int> second = {5, 6, 7};    // after a gap of one edge
  const std::string eseg = writeLabelled("gap", grid, {first, branch, second});
  const AttachmentCurve curve = extractAttachmentCurve(grid, readEseg(eseg, grid), 2);
  EXPECT_EQ(curve.vertices, (std::vector<int>{0, 1, 2, 3, 5, 6, 7}));
  EXPECT_EQ(curve.components, 2);
  EXPECT_EQ(curve.joined, 1);
  EXPECT_EQ(curve.droppedVertices, 1);
  EXPECT_NEAR(curve.gapLength, 2.0, 1e-12);
  EXPECT_NEAR(curve.length, 7.0, 1e-12);

  const AttachmentCurve alone = extractAttachmentCurve(grid, readEseg(eseg, grid), 2, "gap", 1.5);
  EXPECT_EQ(alone.vertices, first);
  EXPECT_EQ(alone.droppedVertices, 4);
}

TEST(AttachmentCurve, MissingLabelIsAnError) {
  const TriMesh grid = makeGrid(3);
  const std::string eseg = writeLabelled("none", grid, {});
  try {
    extractAttachmentCurve(grid, readEseg(eseg, grid), 2, "none.eseg");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "none.eseg: no edge carries label 2");
  }
}

}  // namespace
}  // namespace bcassim
