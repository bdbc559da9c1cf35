#include "bcassim/mesh/MeshValidation.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

double signedVolume(const TetMesh& mesh, Eigen::Index t) {
  const Eigen::Vector3d a = mesh.V.row(mesh.T(t, 0));
  const Eigen::Vector3d b = mesh.V.row(mesh.T(t, 1));
  const Eigen::Vector3d c = mesh.V.row(mesh.T(t, 2));
  const Eigen::Vector3d d = mesh.V.row(mesh.T(t, 3));
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

void validateTetMesh(TetMesh& mesh, const std::string& source) {
  if (mesh.numNodes() == 0) throw InputError(fmt::format("{}: mesh has no nodes", source));
  if (mesh.numTets() == 0) throw InputError(fmt::format("{}: mesh has no tetrahedra", source));
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(mesh.V(i, k)))
        throw InputError(
            fmt::format("{}: node {} has a non-finite coordinate ({}); expected a finite "
                        "number in metres",
                        source, i, mesh.V(i, k)));
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int k = 0; k < 4; ++k)
      if (mesh.T(t, k) < 0 || mesh.T(t, k) >= mesh.numNodes())
        throw InputError(fmt::format("{}: tet {} refers to node {}; expected an index in [0, {})",
                                     source, t, mesh.T(t, k), mesh.numNodes()));
  if (mesh.region.size() != 0 && mesh.region.size() != mesh.numTets())
    throw InputError(
        fmt::format("{}: {} region ids for {} tets", source, mesh.region.size(), mesh.numTets()));

  // Degeneracy is judged relative to the tet's own size, so units do not matter.
  Eigen::Index positive = 0, firstNegative = -1, firstPositive = -1;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const double v = signedVolume(mesh, t);
    double edge = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edge = std::max(edge, (mesh.V.row(mesh.T(t, i)) - mesh.V.row(mesh.T(t, j))).norm());
    if (std::abs(v) <= 1e-12 * edge * edge * edge)
      throw InputError(
          fmt::format("{}: tet {} is degenerate (volume {:.3g} m^3); expected a "
                      "non-flat tetrahedron",
                      source, t, v));
    if (v > 0) {
      ++positive;
      if (firstPositive < 0) firstPositive = t;
    } else if (firstNegative < 0) {
      firstNegative = t;
    }
  }
  if (positive == mesh.numTets()) return;
  if (positive == 0) {  // consistently reversed convention: flip every tet
    mesh.T.col(2).swap(mesh.T.col(3));
    return;
  }
  // Mixed: the minority orientation is the inverted one.
  const bool negativeIsMinority = positive * 2 >= mesh.numTets();
  const Eigen::Index bad = negativeIsMinority ? firstNegative : firstPositive;
  throw InputError(
      fmt::format("{}: tet {} is inverted (signed volume {:.3g} m^3); expected the same "
                  "orientation as the other tets",
                  source, bad, signedVolume(mesh, bad)));
}

}  // namespace bcassim
