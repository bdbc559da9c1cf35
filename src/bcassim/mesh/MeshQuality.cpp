#include "bcassim/mesh/MeshQuality.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {

void tetDihedralRangeDeg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& minDeg,
                         double& maxDeg) {
  const Vec3* p[4] = {&a, &b, &c, &d};
  // Edge (i,j) with the other two vertices (k,l).
  constexpr int kEdges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  minDeg = 180.0;
  maxDeg = 0.0;
  for (const auto& e : kEdges) {
    const Vec3 axis = *p[e[1]] - *p[e[0]];
    const double len2 = axis.squaredNorm();
    // The dihedral angle is the angle between the two other vertices projected onto the plane
    // normal to the edge.
    Vec3 u = *p[e[2]] - *p[e[0]], v = *p[e[3]] - *p[e[0]];
    if (len2 > 0) {
      u -= axis * (u.dot(axis) / len2);
      v -= axis * (v.dot(axis) / len2);
    }
    const double angle = std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / std::numbers::pi;
    minDeg = std::min(minDeg, angle);
    maxDeg = std::max(maxDeg, angle);
  }
}

MeshQuality measureQuality(const TetMesh& mesh) {
  MeshQuality q;
  q.numNodes = mesh.numNodes();
  q.numTets = mesh.numTets();
  if (q.numNodes > 0) {
    q.bboxMin = mesh.V.colwise().minCoeff().transpose();
    q.bboxMax = mesh.V.colwise().maxCoeff().transpose();
  }
  if (q.numTets == 0) return q;
  q.minDihedralDeg = 180.0;
  q.minVolume = std::numeric_limits<double>::infinity();
  q.maxVolume = -std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < q.numTets; ++t) {
    const double v = signedVolume(mesh, t);
    q.minVolume = std::min(q.minVolume, v);
    q.maxVolume = std::max(q.maxVolume, v);
    q.totalVolume += v;
    if (v < 0) ++q.numInverted;
    double lo, hi;
    tetDihedralRangeDeg(mesh.V.row(mesh.T(t, 0)), mesh.V.row(mesh.T(t, 1)),
                        mesh.V.row(mesh.T(t, 2)), mesh.V.row(mesh.T(t, 3)), lo, hi);
    q.minDihedralDeg = std::min(q.minDihedralDeg, lo);
    q.maxDihedralDeg = std::max(q.maxDihedralDeg, hi);
  }
  return q;
}

}  // namespace bcassim
