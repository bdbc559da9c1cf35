#include "bcassim/mesh/BarycentricMap.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/LU>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"

namespace bcassim {

namespace {
constexpr double kWeightTolerance = 1e-10;
}  // namespace

TetLocator::TetLocator(const TetMesh& mesh) {
  const Eigen::Index nt = mesh.numTets();
  if (nt == 0) throw InputError("point mapping: mesh has no tetrahedra; expected at least one");
  const BoundarySurface boundary = extractBoundary(mesh);  // also checks the node indices
  boundary_ = SurfaceLocator(toTriMesh(mesh, boundary));
  faceTet_.assign(boundary.faceTet.data(), boundary.faceTet.data() + boundary.faceTet.size());
  faceLocal_.resize(faceTet_.size());
  for (size_t f = 0; f < faceTet_.size(); ++f)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 4; ++k)
        if (mesh.T(faceTet_[f], k) == boundary.F(f, c)) faceLocal_[f][c] = k;

  frames_.resize(nt);
  std::vector<AabbTree::Box> boxes(nt);
  for (Eigen::Index t = 0; t < nt; ++t) {
    const Vec3 a = mesh.V.row(mesh.T(t, 0)), b = mesh.V.row(mesh.T(t, 1)),
               c = mesh.V.row(mesh.T(t, 2)), d = mesh.V.row(mesh.T(t, 3));
    Mat3 edges;
    edges << b - a, c - a, d - a;
    bool invertible;
    double det;
    edges.computeInverseAndDetWithCheck(frames_[t].inverseEdges, det, invertible);
    frames_[t].origin = a;
    frames_[t].valid = invertible && det != 0.0;
    for (const Vec3* p : {&a, &b, &c, &d}) boxes[t].extend(*p);
  }
  tree_ = AabbTree(boxes);
  const AabbTree::Box& all = tree_.bounds();
  boxTolerance_ = kWeightTolerance * (all.max - all.min).norm();
}

MappedPoint TetLocator::locate(const Vec3& p) const {
  MappedPoint mp;
  tree_.visitContaining(p, boxTolerance_, [&](int t) {
    const TetFrame& f = frames_[t];
    if (!f.valid) return false;
    const Vec3 w = f.inverseEdges * (p - f.origin);
    const Vec4 weights(1.0 - w.sum(), w(0), w(1), w(2));
    if (weights.minCoeff() < -kWeightTolerance) return false;
    mp.tet = t;
    mp.weights = weights;
    mp.inside = true;
    mp.distance = 0.0;
    return true;
  });
  if (mp.inside) return mp;
  // Outside every tet, the nearest point of the mesh lies on its boundary surface.
  const SurfacePoint s = boundary_.closest(p);
  mp.tet = faceTet_[s.face];
  mp.weights.setZero();
  for (int c = 0; c < 3; ++c) mp.weights(faceLocal_[s.face][c]) = s.barycentric(c);
  mp.distance = s.distance;
  return mp;
}

std::vector<MappedPoint> mapPoints(const TetLocator& locator, const Eigen::MatrixX3d& points) {
  std::vector<MappedPoint> out(points.rows());
  tbb::parallel_for(Eigen::Index{0}, points.rows(),
                    [&](Eigen::Index i) { out[i] = locator.locate(points.row(i).transpose()); });
  return out;
}

std::vector<MappedPoint> mapPoints(const TetMesh& mesh, const Eigen::MatrixX3d& points) {
  return mapPoints(TetLocator(mesh), points);
}

Vec3 interpolate(const MappedPoint& mp, const TetMesh& mesh, const Eigen::VectorXd& positions) {
  if (positions.size() != 3 * mesh.numNodes())
    throw InputError(fmt::format("interpolation: {} position entries; expected 3 per node = {}",
                                 positions.size(), 3 * mesh.numNodes()));
  Vec3 x = Vec3::Zero();
  for (int k = 0; k < 4; ++k) x += mp.weights(k) * node(positions, mesh.T(mp.tet, k));
  return x;
}

Vec3 interpolate(const MappedPoint& mp, const TetMesh& mesh) {
  Vec3 x = Vec3::Zero();
  for (int k = 0; k < 4; ++k) x += mp.weights(k) * mesh.V.row(mesh.T(mp.tet, k)).transpose();
  return x;
}

}  // namespace bcassim
