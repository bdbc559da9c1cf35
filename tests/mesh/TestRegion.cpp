// Region selection on a small box mesh whose node positions are known exactly.
#include <gtest/gtest.h>

#include "bcassim/Error.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/Region.h"

namespace bcassim {
namespace {

// 4x3x2 nodes at integer metres: node (i,j,k) = i + 4*(j + 3*k), x=i, y=j, z=k.
TetMesh grid() { return makeBoxMesh(Vec3(3, 2, 1), 3, 2, 1); }
int id(int i, int j, int k) { return i + 4 * (j + 3 * k); }

// Nodes satisfying pred, by brute force over the grid indices, sorted.
template <class Pred>
std::vector<int> expected(Pred pred) {
  std::vector<int> out;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        if (pred(i, j, k)) out.push_back(id(i, j, k));
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Region, BoxIncludesItsBoundary) {
  const auto got = selectNodes(grid(), BoxRegion{Vec3(1, 0, 0), Vec3(2, 1, 1)});
  EXPECT_EQ(got, expected([](int i, int j, int) { return i >= 1 && i <= 2 && j <= 1; }));
}

TEST(Region, Sphere) {
  const auto got = selectNodes(grid(), SphereRegion{Vec3(0, 0, 0), 1.0});
  EXPECT_EQ(got, (std::vector<int>{id(0, 0, 0), id(1, 0, 0), id(0, 1, 0), id(0, 0, 1)}));
}

TEST(Region, HalfSpaceSelectsNonNegativeSide) {
  // x + y >= 3, normal not normalised.
  const auto got = selectNodes(grid(), HalfSpaceRegion{Vec3(3, 0, 0), Vec3(2, 2, 0)});
  EXPECT_EQ(got, expected([](int i, int j, int) { return i + j >= 3; }));
}

TEST(Region, IndexListIsSortedAndUnique) {
  EXPECT_EQ(selectNodes(grid(), IndexListRegion{{7, 2, 7, 0}}), (std::vector<int>{0, 2, 7}));
  EXPECT_EQ(selectTets(grid(), IndexListRegion{{35, 1}}), (std::vector<int>{1, 35}));
}

TEST(Region, IndexOutOfRangeIsRejected) {
  try {
    selectNodes(grid(), IndexListRegion{{3, 24}});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "index list region: node 24 out of range; expected [0, 24)");
  }
  EXPECT_THROW(selectTets(grid(), IndexListRegion{{36}}), InputError);
}

TEST(Region, SurfacePatchWithinBox) {
  // Every node of this mesh is on the surface (no interior nodes), so the patch is the box's.
  const auto got =
      selectNodes(grid(), SurfacePatchRegion{BoxRegion{Vec3(-1, -1, -1), Vec3(1, 5, 5)}, {}});
  EXPECT_EQ(got, expected([](int i, int, int) { return i <= 1; }));
}

TEST(Region, SurfacePatchByNormalDirection) {
  const SphereRegion everywhere{Vec3(0, 0, 0), 100.0};
  // Only nodes inside the top face have a normal exactly +z; nodes on its rim mix in a side
  // face's normal, tilting theirs by tens of degrees.
  const auto flat = selectNodes(grid(), SurfacePatchRegion{everywhere, Vec3(0, 0, 5), 1.0});
  EXPECT_EQ(flat, (std::vector<int>{id(1, 1, 1), id(2, 1, 1)}));
  // Every top node's normal has a positive z component, every bottom node's a negative one.
  const auto upper = selectNodes(grid(), SurfacePatchRegion{everywhere, Vec3(0, 0, 1), 80.0});
  EXPECT_EQ(upper, expected([](int, int, int k) { return k == 1; }));
}

TEST(Region, TetsByCentroid) {
  // Hexes with x in [0,1]: 2 of them along y, 6 tets each.
  const auto got = selectTets(grid(), BoxRegion{Vec3(0, 0, 0), Vec3(1, 2, 1)});
  std::vector<int> want;
  for (int j = 0; j < 2; ++j)
    for (int p = 0; p < 6; ++p) want.push_back(6 * (0 + 3 * j) + p);
  EXPECT_EQ(got, want);
}

TEST(Region, SurfacePatchTetsOwnWholePatchFaces) {
  const TetMesh m = grid();
  const BoxRegion bottom{Vec3(-1, -1, -0.5), Vec3(4, 3, 0.5)};
  const auto tets = selectTets(m, SurfacePatchRegion{bottom, {}});
  // 6 hexes with 2 bottom triangles each, in distinct tets (a tet has one face per plane).
  ASSERT_EQ(tets.size(), 12u);
  for (int t : tets) {
    int onBottom = 0;
    for (int k = 0; k < 4; ++k) onBottom += m.V(m.T(t, k), 2) == 0.0;
    EXPECT_EQ(onBottom, 3) << "tet " << t;
  }
  EXPECT_TRUE(selectTets(m, SurfacePatchRegion{bottom, Vec3(0, 0, 1), 80.0}).empty());
}

TEST(Region, EmptySelectionIsNotAnError) {
  EXPECT_TRUE(selectNodes(grid(), SphereRegion{Vec3(10, 10, 10), 0.5}).empty());
  EXPECT_TRUE(selectTets(grid(), BoxRegion{Vec3(10, 10, 10), Vec3(11, 11, 11)}).empty());
}

TEST(Region, IllFormedRegionsAreRejected) {
  EXPECT_THROW(selectNodes(grid(), BoxRegion{Vec3(1, 0, 0), Vec3(0, 1, 1)}), InputError);
  EXPECT_THROW(selectNodes(grid(), SphereRegion{Vec3(0, 0, 0), -1.0}), InputError);
  EXPECT_THROW(selectNodes(grid(), HalfSpaceRegion{Vec3(0, 0, 0), Vec3(0, 0, 0)}), InputError);
  EXPECT_THROW(
      selectNodes(grid(), SurfacePatchRegion{SphereRegion{Vec3(0, 0, 0), 1}, Vec3(0, 0, 0), 10}),
      InputError);
}

}  // namespace
}  // namespace bcassim
