#include "bcassim/mesh/BoundarySurface.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>

#include "bcassim/Error.h"

namespace bcassim {

namespace {
// Local faces of a positively oriented tet (a,b,c,d), each counter-clockwise seen from outside:
// face k is opposite local vertex k.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct FaceKey {
  std::array<int, 3> sorted;
  int tet;
  int local;
};
}  // namespace

BoundarySurface extractBoundary(const TetMesh& mesh) {
  const Eigen::Index nt = mesh.numTets(), nv = mesh.numNodes();
  std::vector<FaceKey> keys;
  keys.reserve(4 * nt);
  for (Eigen::Index t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> s = {mesh.T(t, kFace[k][0]), mesh.T(t, kFace[k][1]),
                              mesh.T(t, kFace[k][2])};
      for (int v : s)
        if (v < 0 || v >= nv)
          throw InputError(fmt::format(
              "boundary extraction: tet {} refers to node {}; expected an index in [0, {})", t, v,
              nv));
      std::sort(s.begin(), s.end());
      keys.push_back({s, static_cast<int>(t), k});
    }
  std::sort(keys.begin(), keys.end(), [](const FaceKey& a, const FaceKey& b) {
    return a.sorted != b.sorted ? a.sorted < b.sorted
                                : std::pair(a.tet, a.local) < std::pair(b.tet, b.local);
  });

  std::vector<std::pair<int, int>> owners;  // (tet, local face) of faces seen once
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j].sorted == keys[i].sorted) ++j;
    if (j - i == 1) owners.emplace_back(keys[i].tet, keys[i].local);
    if (j - i > 2)
      throw InputError(fmt::format(
          "boundary extraction: face ({}, {}, {}) is shared by {} tets; expected at most 2",
          keys[i].sorted[0], keys[i].sorted[1], keys[i].sorted[2], j - i));
    i = j;
  }
  std::sort(owners.begin(), owners.end());

  BoundarySurface s;
  const Eigen::Index nf = static_cast<Eigen::Index>(owners.size());
  s.F.resize(nf, 3);
  s.faceTet.resize(nf);
  s.faceNormals.setZero(nf, 3);
  s.vertexNormals.setZero(nv, 3);
  std::vector<char> onSurface(nv, 0);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const auto [t, k] = owners[f];
    for (int c = 0; c < 3; ++c) {
      s.F(f, c) = mesh.T(t, kFace[k][c]);
      onSurface[s.F(f, c)] = 1;
    }
    s.faceTet(f) = t;
    const Vec3 a = mesh.V.row(s.F(f, 0)), b = mesh.V.row(s.F(f, 1)), c = mesh.V.row(s.F(f, 2));
    const Vec3 areaVector = (b - a).cross(c - a);  // twice the area, along the normal
    for (int c2 = 0; c2 < 3; ++c2) s.vertexNormals.row(s.F(f, c2)) += areaVector.transpose();
    const double n = areaVector.norm();
    if (n > 0) s.faceNormals.row(f) = areaVector.transpose() / n;
  }
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (onSurface[v]) s.nodes.push_back(static_cast<int>(v));
    const double n = s.vertexNormals.row(v).norm();
    if (n > 0) s.vertexNormals.row(v) /= n;
  }
  return s;
}

TriMesh toTriMesh(const TetMesh& mesh, const BoundarySurface& boundary) {
  std::vector<int> compact(mesh.numNodes(), -1);
  TriMesh out;
  out.V.resize(static_cast<Eigen::Index>(boundary.nodes.size()), 3);
  for (size_t i = 0; i < boundary.nodes.size(); ++i) {
    compact[boundary.nodes[i]] = static_cast<int>(i);
    out.V.row(i) = mesh.V.row(boundary.nodes[i]);
  }
  out.F.resize(boundary.F.rows(), 3);
  for (Eigen::Index f = 0; f < boundary.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) out.F(f, c) = compact[boundary.F(f, c)];
  return out;
}

}  // namespace bcassim
