#include "bcassim/atlas/OrientedFaces.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "bcassim/Error.h"

namespace bcassim {
namespace {
// Spreads the low 10 bits of v to every third bit.
std::uint32_t spreadBits(std::uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

// Face indices sorted by the Morton code of their centres on a 1024^3 grid over their box.
std::vector<int> mortonOrder(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const Eigen::Index nf = F.rows();
  Eigen::MatrixX3d c(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    c.row(f) = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
  }
  std::vector<int> order(static_cast<size_t>(nf));
  std::iota(order.begin(), order.end(), 0);
  if (nf == 0) return order;
  const Eigen::RowVector3d lo = c.colwise().minCoeff();
  const double extent = (c.colwise().maxCoeff() - lo).maxCoeff();
  const double scale = extent > 0.0 ? 1023.0 / extent : 0.0;
  std::vector<std::uint32_t> code(static_cast<size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    std::uint32_t key = 0;
    for (int d = 0; d < 3; ++d) {
      const auto q = static_cast<std::uint32_t>((c(f, d) - lo(d)) * scale);
      key |= spreadBits(q) << d;
    }
    code[f] = key;
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return code[a] < code[b]; });
  return order;
}
}  // namespace

OrientedFaces orientedFaces(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())) {
    throw InputError(fmt::format("triangle vertex index out of range [0, {})", V.rows()));
  }
  const auto nf = static_cast<size_t>(F.rows());
  OrientedFaces o;
  for (auto* v : {&o.cx, &o.cy, &o.cz, &o.nx, &o.ny, &o.nz, &o.invNorm}) v->resize(nf);
  o.face = mortonOrder(V, F);
  for (size_t slot = 0; slot < nf; ++slot) {
    const int f = o.face[slot];
    const Eigen::Vector3d v0 = V.row(F(f, 0)), v1 = V.row(F(f, 1)), v2 = V.row(F(f, 2));
    const Eigen::Vector3d c = (v0 + v1 + v2) / 3.0;
    const Eigen::Vector3d n = 0.5 * (v1 - v0).cross(v2 - v0);
    const double norm = n.norm();
    o.cx[slot] = c.x();
    o.cy[slot] = c.y();
    o.cz[slot] = c.z();
    o.nx[slot] = n.x();
    o.ny[slot] = n.y();
    o.nz[slot] = n.z();
    o.invNorm[slot] = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  return o;
}

void addFaceGradientToVertices(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                               const OrientedFaces& faces, const Eigen::MatrixX3d& gc,
                               const Eigen::MatrixX3d& gn, Eigen::MatrixX3d* gV) {
  for (Eigen::Index slot = 0; slot < faces.size(); ++slot) {
    const int f = faces.face[slot];
    const Eigen::RowVector3d v0 = V.row(F(f, 0)), v1 = V.row(F(f, 1)), v2 = V.row(F(f, 2));
    const Eigen::RowVector3d c = gc.row(slot) / 3.0, g = 0.5 * gn.row(slot);
    // d(g . (v1 - v0) x (v2 - v0)) / dv0 = g x (v2 - v1), and cyclically.
    gV->row(F(f, 0)) += c + g.cross(v2 - v1);
    gV->row(F(f, 1)) += c + g.cross(v0 - v2);
    gV->row(F(f, 2)) += c + g.cross(v1 - v0);
  }
}

}  // namespace bcassim
