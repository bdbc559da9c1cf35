#include "bcassim/scene/NodePoints.h"

#include <limits>

#include "bcassim/Error.h"

namespace bcassim {

std::vector<int> tetOfEachNode(const TetMesh& mesh) {
  std::vector<int> tetOf(mesh.numNodes(), -1);
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    for (int a = 0; a < 4; ++a)
      if (tetOf[mesh.T(t, a)] < 0) tetOf[mesh.T(t, a)] = static_cast<int>(t);
  return tetOf;
}

MappedPoint mappedNode(const TetMesh& mesh, const std::vector<int>& tetOfNode, int node) {
  const int t = tetOfNode.at(node);
  if (t < 0) throw InputError("node " + std::to_string(node) + " belongs to no tetrahedron");
  MappedPoint mp;
  mp.tet = t;
  mp.weights.setZero();
  for (int a = 0; a < 4; ++a)
    if (mesh.T(t, a) == node) mp.weights(a) = 1.0;
  mp.inside = true;
  return mp;
}

std::vector<int> farthestPointSample(const TetMesh& mesh, const std::vector<int>& nodes,
                                     int count) {
  const size_t n = nodes.size();
  const size_t want = std::min(n, static_cast<size_t>(std::max(count, 0)));
  std::vector<int> taken;
  if (want == 0) return taken;
  Vec3 centroid = Vec3::Zero();
  for (int v : nodes) centroid += mesh.V.row(v).transpose();
  centroid /= static_cast<double>(n);
  // dist[i]: squared distance of nodes[i] to the nearest taken node (to the centroid at first).
  std::vector<double> dist(n);
  for (size_t i = 0; i < n; ++i)
    dist[i] = (mesh.V.row(nodes[i]).transpose() - centroid).squaredNorm();
  while (taken.size() < want) {
    size_t best = 0;
    for (size_t i = 1; i < n; ++i)
      if (dist[i] > dist[best]) best = i;
    taken.push_back(nodes[best]);
    const Vec3 p = mesh.V.row(nodes[best]).transpose();
    const bool first = taken.size() == 1;
    for (size_t i = 0; i < n; ++i) {
      const double d = (mesh.V.row(nodes[i]).transpose() - p).squaredNorm();
      if (dist[i] >= 0) dist[i] = first ? d : std::min(dist[i], d);
    }
    dist[best] = -1.0;  // never again, even when all remaining nodes coincide with taken ones
  }
  return taken;
}

}  // namespace bcassim
