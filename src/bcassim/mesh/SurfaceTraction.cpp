#include "bcassim/mesh/SurfaceTraction.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <variant>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"

namespace bcassim {

SurfaceTractionShares surfaceTractionShares(const TetMesh& mesh, const Region& region,
                                            int subdivisions) {
  const int m = std::max(1, subdivisions);
  const BoundarySurface boundary = extractBoundary(mesh);
  std::vector<char> listed;
  if (std::holds_alternative<IndexListRegion>(region)) {
    listed.assign(mesh.numNodes(), 0);
    for (int i : selectNodes(mesh, region)) listed[i] = 1;  // checks the ids
  }
  // Barycentric coordinates (of nodes 1 and 2) of the m^2 sub-triangle centroids: m(m+1)/2
  // upward and m(m-1)/2 downward sub-triangles, all of area 1/m^2 of the face.
  std::vector<std::pair<double, double>> centroids;
  for (int i = 0; i < m; ++i)
    for (int j = 0; i + j < m; ++j) {
      centroids.emplace_back((i + 1.0 / 3) / m, (j + 1.0 / 3) / m);
      if (i + j < m - 1) centroids.emplace_back((i + 2.0 / 3) / m, (j + 2.0 / 3) / m);
    }

  Eigen::VectorXd load = Eigen::VectorXd::Zero(mesh.numNodes());
  double area = 0;
  for (Eigen::Index f = 0; f < boundary.F.rows(); ++f) {
    const int a = boundary.F(f, 0), b = boundary.F(f, 1), c = boundary.F(f, 2);
    const Vec3 xa = mesh.V.row(a), xb = mesh.V.row(b), xc = mesh.V.row(c);
    const double faceArea = 0.5 * (xb - xa).cross(xc - xa).norm();
    if (!listed.empty()) {
      if (!(listed[a] && listed[b] && listed[c])) continue;
      for (int n : {a, b, c}) load(n) += faceArea / 3;
      area += faceArea;
      continue;
    }
    const Vec3 normal = boundary.faceNormals.row(f);
    const double subArea = faceArea / (m * m);
    for (const auto& [s, t] : centroids) {
      if (!containsSurfacePoint(region, (1 - s - t) * xa + s * xb + t * xc, normal)) continue;
      load(a) += (1 - s - t) * subArea;
      load(b) += s * subArea;
      load(c) += t * subArea;
      area += subArea;
    }
  }
  if (!(area > 0))
    throw InputError(
        "the region holds no part of the boundary surface; expected a region that a surface load "
        "can act on");
  SurfaceTractionShares out;
  out.area = area;
  for (Eigen::Index n = 0; n < load.size(); ++n)
    if (load(n) > 0) {
      out.nodes.push_back(static_cast<int>(n));
      out.shares.push_back(load(n) / area);
    }
  return out;
}

}  // namespace bcassim
