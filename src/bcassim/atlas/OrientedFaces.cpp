#include "bcassim/atlas/OrientedFaces.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

OrientedFaces orientedFaces(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())) {
    throw InputError(fmt::format("triangle vertex index out of range [0, {})", V.rows()));
  }
  const auto nf = static_cast<size_t>(F.rows());
  OrientedFaces o;
  for (auto* v : {&o.cx, &o.cy, &o.cz, &o.nx, &o.ny, &o.nz, &o.invNorm}) v->resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d v0 = V.row(F(f, 0)), v1 = V.row(F(f, 1)), v2 = V.row(F(f, 2));
    const Eigen::Vector3d c = (v0 + v1 + v2) / 3.0;
    const Eigen::Vector3d n = 0.5 * (v1 - v0).cross(v2 - v0);
    const double norm = n.norm();
    o.cx[f] = c.x();
    o.cy[f] = c.y();
    o.cz[f] = c.z();
    o.nx[f] = n.x();
    o.ny[f] = n.y();
    o.nz[f] = n.z();
    o.invNorm[f] = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  return o;
}

void addFaceGradientToVertices(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                               const Eigen::MatrixX3d& gc, const Eigen::MatrixX3d& gn,
                               Eigen::MatrixX3d* gV) {
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d v0 = V.row(F(f, 0)), v1 = V.row(F(f, 1)), v2 = V.row(F(f, 2));
    const Eigen::RowVector3d c = gc.row(f) / 3.0, g = 0.5 * gn.row(f);
    // d(g . (v1 - v0) x (v2 - v0)) / dv0 = g x (v2 - v1), and cyclically.
    gV->row(F(f, 0)) += c + g.cross(v2 - v1);
    gV->row(F(f, 1)) += c + g.cross(v0 - v2);
    gV->row(F(f, 2)) += c + g.cross(v1 - v0);
  }
}

}  // namespace bcassim
