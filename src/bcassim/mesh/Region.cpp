#include "bcassim/mesh/Region.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/mesh/BoundarySurface.h"

namespace bcassim {

namespace {

void check(const BoxRegion& r) {
  if (!(r.min.array() <= r.max.array()).all())
    throw InputError(fmt::format(
        "box region: min ({}, {}, {}) exceeds max ({}, {}, {}); expected min <= max per axis",
        r.min(0), r.min(1), r.min(2), r.max(0), r.max(1), r.max(2)));
}
void check(const SphereRegion& r) {
  if (!(r.radius >= 0))
    throw InputError(
        fmt::format("sphere region: radius {} m; expected a non-negative radius", r.radius));
}
void check(const HalfSpaceRegion& r) {
  if (!(r.normal.squaredNorm() > 0))
    throw InputError("half-space region: normal is zero; expected a non-zero normal vector");
}

bool contains(const BoxRegion& r, const Vec3& x) {
  return (x.array() >= r.min.array()).all() && (x.array() <= r.max.array()).all();
}
bool contains(const SphereRegion& r, const Vec3& x) {
  return (x - r.center).squaredNorm() <= r.radius * r.radius;
}
bool contains(const HalfSpaceRegion& r, const Vec3& x) { return (x - r.point).dot(r.normal) >= 0; }

template <class Shape>
std::vector<int> pointsIn(const Shape& shape, Eigen::Index n, auto&& pointOf) {
  check(shape);
  std::vector<int> out;
  for (Eigen::Index i = 0; i < n; ++i)
    if (contains(shape, pointOf(i))) out.push_back(static_cast<int>(i));
  return out;
}

std::vector<int> checkedIndices(const IndexListRegion& r, Eigen::Index n, const char* what) {
  std::vector<int> out = r.indices;
  for (int i : out)
    if (i < 0 || i >= n)
      throw InputError(
          fmt::format("index list region: {} {} out of range; expected [0, {})", what, i, n));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> patchNodes(const TetMesh& mesh, const SurfacePatchRegion& r,
                            const BoundarySurface& boundary) {
  std::visit([](const auto& s) { check(s); }, r.within);
  double cosMax = -1.0;
  Vec3 dir = Vec3::Zero();
  if (r.direction) {
    if (!(r.direction->squaredNorm() > 0))
      throw InputError(
          "surface patch region: direction is zero; expected a non-zero direction vector");
    dir = r.direction->normalized();
    cosMax = std::cos(r.maxAngleDeg * std::numbers::pi / 180.0);
  }
  std::vector<int> out;
  for (int v : boundary.nodes) {
    const Vec3 x = mesh.V.row(v);
    if (!std::visit([&](const auto& s) { return contains(s, x); }, r.within)) continue;
    if (r.direction && boundary.vertexNormals.row(v).dot(dir) < cosMax) continue;
    out.push_back(v);
  }
  return out;
}

Vec3 centroid(const TetMesh& mesh, Eigen::Index t) {
  return 0.25 * (mesh.V.row(mesh.T(t, 0)) + mesh.V.row(mesh.T(t, 1)) + mesh.V.row(mesh.T(t, 2)) +
                 mesh.V.row(mesh.T(t, 3)))
                    .transpose();
}

}  // namespace

std::vector<int> selectNodes(const TetMesh& mesh, const Region& region) {
  auto position = [&](Eigen::Index i) -> Vec3 { return mesh.V.row(i).transpose(); };
  return std::visit(
      [&](const auto& r) -> std::vector<int> {
        using R = std::decay_t<decltype(r)>;
        if constexpr (std::is_same_v<R, IndexListRegion>)
          return checkedIndices(r, mesh.numNodes(), "node");
        else if constexpr (std::is_same_v<R, SurfacePatchRegion>)
          return patchNodes(mesh, r, extractBoundary(mesh));
        else
          return pointsIn(r, mesh.numNodes(), position);
      },
      region);
}

std::vector<int> selectTets(const TetMesh& mesh, const Region& region) {
  auto center = [&](Eigen::Index t) { return centroid(mesh, t); };
  return std::visit(
      [&](const auto& r) -> std::vector<int> {
        using R = std::decay_t<decltype(r)>;
        if constexpr (std::is_same_v<R, IndexListRegion>) {
          return checkedIndices(r, mesh.numTets(), "tet");
        } else if constexpr (std::is_same_v<R, SurfacePatchRegion>) {
          const BoundarySurface boundary = extractBoundary(mesh);
          const std::vector<int> nodes = patchNodes(mesh, r, boundary);
          std::vector<char> inPatch(mesh.numNodes(), 0);
          for (int v : nodes) inPatch[v] = 1;
          std::vector<int> out;
          for (Eigen::Index f = 0; f < boundary.F.rows(); ++f)
            if (inPatch[boundary.F(f, 0)] && inPatch[boundary.F(f, 1)] && inPatch[boundary.F(f, 2)])
              out.push_back(boundary.faceTet(f));
          std::sort(out.begin(), out.end());
          out.erase(std::unique(out.begin(), out.end()), out.end());
          return out;
        } else {
          return pointsIn(r, mesh.numTets(), center);
        }
      },
      region);
}

bool containsSurfacePoint(const Region& region, const Vec3& x, const Vec3& faceNormal) {
  return std::visit(
      [&](const auto& r) -> bool {
        using R = std::decay_t<decltype(r)>;
        if constexpr (std::is_same_v<R, IndexListRegion>) {
          throw std::logic_error("containsSurfacePoint: an index list region holds no points");
        } else if constexpr (std::is_same_v<R, SurfacePatchRegion>) {
          std::visit([](const auto& s) { check(s); }, r.within);
          if (!std::visit([&](const auto& s) { return contains(s, x); }, r.within)) return false;
          if (!r.direction) return true;
          if (!(r.direction->squaredNorm() > 0))
            throw InputError(
                "surface patch region: direction is zero; expected a non-zero direction vector");
          return faceNormal.dot(r.direction->normalized()) >=
                 std::cos(r.maxAngleDeg * std::numbers::pi / 180.0);
        } else {
          check(r);
          return contains(r, x);
        }
      },
      region);
}

}  // namespace bcassim
