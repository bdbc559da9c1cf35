// Helpers of the ligaments tests: the shared data directory and a synthetic icosphere surface.
#pragma once
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim::test {

// BCASSIM_DATA, else <source>/../shared/data; empty when neither exists.
inline std::string ligamentDataDir() {
  if (const char* env = std::getenv("BCASSIM_DATA"); env && std::filesystem::is_directory(env)) {
    return env;
  }
  const std::string dir = std::string(BCASSIM_SOURCE_DIR) + "/../shared/data";
  return std::filesystem::is_directory(dir + "/livers") ? dir : std::string();
}

// Outward-oriented icosphere of `radius` (m) centred at the origin, `levels` subdivisions
// (20 * 4^levels faces).
inline TriMesh makeIcosphere(double radius, int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Eigen::MatrixX3d V(12, 3);
  V << -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1,
      t, 0, 1, -t, 0, -1, -t, 0, 1;
  Eigen::MatrixX3i F(20, 3);
  F << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7,
      1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9,
      8, 1;
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    std::vector<Eigen::RowVector3d> verts;
    for (int i = 0; i < V.rows(); ++i) verts.push_back(V.row(i));
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      verts.push_back(0.5 * (verts[a] + verts[b]));
      return mid[key] = static_cast<int>(verts.size()) - 1;
    };
    Eigen::MatrixX3i G(4 * F.rows(), 3);
    for (int f = 0; f < F.rows(); ++f) {
      const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      G.row(4 * f) << a, ab, ca;
      G.row(4 * f + 1) << b, bc, ab;
      G.row(4 * f + 2) << c, ca, bc;
      G.row(4 * f + 3) << ab, bc, ca;
    }
    V.resize(static_cast<Eigen::Index>(verts.size()), 3);
    for (size_t i = 0; i < verts.size(); ++i) V.row(i) = verts[i];
    F = G;
  }
  for (int i = 0; i < V.rows(); ++i) V.row(i) = radius * V.row(i).normalized();
  return {V, F};
}

}  // namespace bcassim::test
