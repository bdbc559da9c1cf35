#include "bcassim/mesh/MeshGenerators.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/mesh/MeshQuality.h"

namespace bcassim {

namespace {

// Makes tet t positively oriented by swapping its last two nodes when needed.
void orientPositive(TetMesh& mesh, Eigen::Index t) {
  const Vec3 a = mesh.V.row(mesh.T(t, 0)), b = mesh.V.row(mesh.T(t, 1)),
             c = mesh.V.row(mesh.T(t, 2)), d = mesh.V.row(mesh.T(t, 3));
  if ((b - a).cross(c - a).dot(d - a) < 0) std::swap(mesh.T(t, 2), mesh.T(t, 3));
}

// Coordinate i of n equal steps over [0, s], with the last one exactly s so that nodes on the far
// faces can be selected by exact comparisons.
double gridCoordinate(double s, int i, int n) { return i == n ? s : s * i / n; }

}  // namespace

TetMesh makeBoxMesh(const Vec3& size, int nx, int ny, int nz) {
  if (!(size.array() > 0).all() || !size.allFinite())
    throw InputError(fmt::format("box mesh: size ({}, {}, {}) m; expected three positive lengths",
                                 size(0), size(1), size(2)));
  if (nx < 1 || ny < 1 || nz < 1)
    throw InputError(
        fmt::format("box mesh: {}x{}x{} cells; expected at least 1 along each axis", nx, ny, nz));
  const Eigen::Index px = nx + 1, py = ny + 1, pz = nz + 1;
  TetMesh mesh;
  mesh.V.resize(px * py * pz, 3);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i)
        mesh.V.row(i + px * (j + py * k)) << gridCoordinate(size(0), i, nx),
            gridCoordinate(size(1), j, ny), gridCoordinate(size(2), k, nz);

  // Kuhn split: one tet per axis permutation (p0,p1,p2), walking 000 -> e_p0 -> e_p0+e_p1 -> 111.
  // Its orientation is the permutation's sign, so odd permutations swap two nodes.
  constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  mesh.T.resize(Eigen::Index{6} * nx * ny * nz, 4);
  Eigen::Index t = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (int p = 0; p < 6; ++p) {
          std::array<int, 3> c = {i, j, k};
          std::array<int, 4> v;
          v[0] = static_cast<int>(c[0] + px * (c[1] + py * c[2]));
          for (int s = 0; s < 3; ++s) {
            ++c[kPerm[p][s]];
            v[s + 1] = static_cast<int>(c[0] + px * (c[1] + py * c[2]));
          }
          if (p >= 3) std::swap(v[2], v[3]);
          mesh.T.row(t++) << v[0], v[1], v[2], v[3];
        }
  mesh.region = Eigen::VectorXi::Zero(mesh.numTets());
  return mesh;
}

TetMesh makeBoxMeshWithTargetTets(const Vec3& size, int targetTets) {
  if (!(size.array() > 0).all() || !size.allFinite())
    throw InputError(fmt::format("box mesh: size ({}, {}, {}) m; expected three positive lengths",
                                 size(0), size(1), size(2)));
  if (targetTets < 1)
    throw InputError(fmt::format("box mesh: target of {} tets; expected at least 1", targetTets));
  // Cubic hexes of side h0 give the target; each axis count is searched around its ideal value
  // independently, since rounding all three with one h can miss the target by far on slender
  // boxes. Among grids whose hex sides differ by at most kMaxAnisotropy, the nearest count wins,
  // ties to the more cubic.
  constexpr double kMaxAnisotropy = 1.5;
  const double h0 = std::cbrt(6.0 * size.prod() / targetTets);
  std::array<int, 3> lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(1, static_cast<int>(std::floor(0.6 * size(a) / h0)));
    hi[a] = std::max(1, static_cast<int>(std::ceil(1.6 * size(a) / h0)));
  }
  std::array<int, 3> best = {1, 1, 1};
  double bestErr = std::numeric_limits<double>::infinity(), bestAniso = 0;
  for (int nx = lo[0]; nx <= hi[0]; ++nx)
    for (int ny = lo[1]; ny <= hi[1]; ++ny)
      for (int nz = lo[2]; nz <= hi[2]; ++nz) {
        const std::array<int, 3> n = {nx, ny, nz};
        // An axis with a single cell cannot get coarser, so a box thinner than a cell along it
        // is not penalised for that axis.
        double hMin = std::numeric_limits<double>::infinity(), hMax = 0;
        for (int a = 0; a < 3; ++a) {
          const double h = size(a) / n[a];
          hMax = std::max(hMax, h);
          if (n[a] > 1) hMin = std::min(hMin, h);
        }
        const double aniso = std::isfinite(hMin) ? hMax / hMin : 1.0;
        if (aniso > kMaxAnisotropy) continue;
        const double err = std::abs(6.0 * nx * ny * nz - targetTets);
        if (err < bestErr || (err == bestErr && aniso < bestAniso)) {
          bestErr = err;
          bestAniso = aniso;
          best = {nx, ny, nz};
        }
      }
  return makeBoxMesh(size, best[0], best[1], best[2]);
}

namespace {

// Disc cross-section of concentric rings: node 0 at the centre, ring k (1..rings) has perRing*k
// nodes at radius radius*k/rings. Triangles are counter-clockwise in the xy plane.
struct Disc {
  std::vector<std::array<double, 2>> xy;
  std::vector<std::array<int, 3>> tri;
};

Disc makeDisc(double radius, int rings, int perRing) {
  Disc d;
  d.xy.push_back({0.0, 0.0});
  std::vector<int> ringStart = {0};
  for (int k = 1; k <= rings; ++k) {
    ringStart.push_back(static_cast<int>(d.xy.size()));
    const int n = perRing * k;
    const double r = k == rings ? radius : radius * k / rings;
    for (int j = 0; j < n; ++j) {
      const double theta = 2.0 * std::numbers::pi * j / n;
      d.xy.push_back({r * std::cos(theta), r * std::sin(theta)});
    }
  }
  for (int j = 0; j < perRing; ++j) d.tri.push_back({0, 1 + j, 1 + (j + 1) % perRing});
  auto dist2 = [&](int a, int b) {
    const double dx = d.xy[a][0] - d.xy[b][0], dy = d.xy[a][1] - d.xy[b][1];
    return dx * dx + dy * dy;
  };
  for (int k = 2; k <= rings; ++k) {
    const int na = perRing * (k - 1), nb = perRing * k;
    auto in = [&](int i) { return ringStart[k - 1] + i % na; };
    auto out = [&](int j) { return ringStart[k] + j % nb; };
    // Zip the two rings, always closing the triangle across the shorter diagonal.
    int i = 0, j = 0;
    while (i < na || j < nb) {
      const bool advanceOuter =
          i == na || (j < nb && dist2(in(i), out(j + 1)) <= dist2(out(j), in(i + 1)));
      if (advanceOuter) {
        d.tri.push_back({in(i), out(j), out(j + 1)});
        ++j;
      } else {
        d.tri.push_back({in(i), out(j), in(i + 1)});
        ++i;
      }
    }
  }
  return d;
}

// Extrudes the disc into `layers` prisms of height length/layers, each cut into 3 tets. Cutting
// every quadrilateral side from its lower-index bottom node to its higher-index top node makes
// the cut depend only on the face, so neighbouring prisms agree.
TetMesh extrudeDisc(const Disc& d, double length, int layers) {
  const int nc = static_cast<int>(d.xy.size());
  TetMesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(nc) * (layers + 1), 3);
  for (int l = 0; l <= layers; ++l) {
    const double z = l == layers ? length : length * l / layers;
    for (int i = 0; i < nc; ++i) mesh.V.row(l * nc + i) << d.xy[i][0], d.xy[i][1], z;
  }
  mesh.T.resize(static_cast<Eigen::Index>(3) * d.tri.size() * layers, 4);
  Eigen::Index t = 0;
  for (int l = 0; l < layers; ++l)
    for (auto tri : d.tri) {
      std::sort(tri.begin(), tri.end());
      const int p = l * nc + tri[0], q = l * nc + tri[1], r = l * nc + tri[2];
      const int p1 = p + nc, q1 = q + nc, r1 = r + nc;
      mesh.T.row(t++) << p, q, r, r1;
      mesh.T.row(t++) << p, q, q1, r1;
      mesh.T.row(t++) << p, p1, q1, r1;
    }
  for (Eigen::Index k = 0; k < t; ++k) orientPositive(mesh, k);
  mesh.region = Eigen::VectorXi::Zero(mesh.numTets());
  return mesh;
}

// Smallest dihedral angle over the tets of one layer; all layers are congruent.
double layerMinDihedral(const Disc& d, double layerHeight) {
  const TetMesh layer = extrudeDisc(d, layerHeight, 1);
  double worst = 180.0;
  for (Eigen::Index t = 0; t < layer.numTets(); ++t) {
    double lo, hi;
    tetDihedralRangeDeg(layer.V.row(layer.T(t, 0)), layer.V.row(layer.T(t, 1)),
                        layer.V.row(layer.T(t, 2)), layer.V.row(layer.T(t, 3)), lo, hi);
    worst = std::min(worst, lo);
  }
  return worst;
}

}  // namespace

TetMesh makeCylinderMesh(double radius, double length, int targetNodes) {
  if (!(radius > 0) || !(length > 0) || !std::isfinite(radius) || !std::isfinite(length))
    throw InputError(
        fmt::format("cylinder mesh: radius {} m, length {} m; expected positive finite lengths",
                    radius, length));
  if (targetNodes < 8)
    throw InputError(
        fmt::format("cylinder mesh: target of {} nodes; expected at least 8", targetNodes));
  // Candidates (rings, nodes per first ring, layers) whose node count is within kTolerance of the
  // target; the one with the best smallest dihedral angle wins, ties to the nearer count.
  constexpr double kTolerance = 0.05;
  struct Choice {
    int rings = 1, perRing = 6, layers = 1;
    double minDihedral = -1, countError = std::numeric_limits<double>::infinity();
  } best, nearest;
  for (int perRing = 4; perRing <= 8; ++perRing)
    for (int rings = 1;; ++rings) {
      const int nc = 1 + perRing * rings * (rings + 1) / 2;
      if (2 * nc > targetNodes * (1 + kTolerance) && rings > 1) break;
      const double radial = radius / rings;
      const int layersFloor = std::max(1, targetNodes / nc - 1);
      for (int layers = layersFloor; layers <= layersFloor + 1; ++layers) {
        const double countError = std::abs(double(nc) * (layers + 1) - targetNodes) / targetNodes;
        if (countError < nearest.countError) nearest = {rings, perRing, layers, -1, countError};
        const double aspect = length / layers / radial;
        if (countError > kTolerance || aspect < 0.25 || aspect > 4) continue;
        const double q = layerMinDihedral(makeDisc(radius, rings, perRing), length / layers);
        if (q > best.minDihedral + 1e-9 ||
            (q > best.minDihedral - 1e-9 && countError < best.countError))
          best = {rings, perRing, layers, q, countError};
      }
    }
  const Choice& c = best.minDihedral >= 0 ? best : nearest;
  return extrudeDisc(makeDisc(radius, c.rings, c.perRing), length, c.layers);
}

TriMesh makeIcosphereSurface(double radius, int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Eigen::MatrixX3d V(12, 3);
  V << -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t,
      0, 1, -t, 0, -1, -t, 0, 1;
  Eigen::MatrixX3i F(20, 3);
  F << 0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7,
      1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8,
      1;
  for (int i = 0; i < V.rows(); ++i) V.row(i).normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    std::vector<Eigen::RowVector3d> verts;
    verts.reserve(static_cast<size_t>(V.rows() + 3 * F.rows()));
    for (int i = 0; i < V.rows(); ++i) verts.push_back(V.row(i));
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      verts.push_back((verts[a] + verts[b]).normalized());  // on the sphere at every level
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
  V *= radius;
  return {V, F};
}

}  // namespace bcassim
