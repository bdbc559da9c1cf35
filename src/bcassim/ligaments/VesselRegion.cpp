// Vessel region selection; the hilum guess is a placeholder for an atlas landmark (thesis ch. 4).
#include "bcassim/ligaments/VesselRegion.h"

#include <algorithm>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"

namespace bcassim {

std::vector<int> nodesWithinRadius(const TetMesh& mesh, const Vec3& center, double radius) {
  std::vector<int> nodes;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) {
    if ((mesh.V.row(i).transpose() - center).norm() <= radius) nodes.push_back(static_cast<int>(i));
  }
  return nodes;
}

Vec3 guessHilumPoint(const TetMesh& mesh, const Eigen::MatrixX3d& curve, const Vec3& posterior,
                     double farFraction) {
  if (mesh.numTets() == 0 || curve.rows() == 0) {
    throw InputError("hilum guess: empty mesh or ligament curve");
  }
  if (!(posterior.norm() > 0) || !(farFraction > 0 && farFraction <= 1)) {
    throw InputError("hilum guess: posterior direction must be non-zero, farFraction in (0, 1]");
  }
  const std::vector<int> surface = extractBoundary(mesh).nodes;
  std::vector<std::pair<double, int>> byDistance;
  for (int node : surface) {
    const Eigen::RowVector3d p = mesh.V.row(node);
    byDistance.push_back({(curve.rowwise() - p).rowwise().squaredNorm().minCoeff(), node});
  }
  std::sort(byDistance.begin(), byDistance.end(), std::greater<>());
  const size_t keep = std::max<size_t>(1, static_cast<size_t>(farFraction * byDistance.size()));
  const Vec3 dir = posterior.normalized();
  int best = byDistance[0].second;
  for (size_t k = 0; k < keep; ++k) {
    const int node = byDistance[k].second;
    if (mesh.V.row(node).dot(dir) > mesh.V.row(best).dot(dir)) best = node;
  }
  return mesh.V.row(best).transpose();
}

}  // namespace bcassim
