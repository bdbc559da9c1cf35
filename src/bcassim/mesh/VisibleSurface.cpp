#include "bcassim/mesh/VisibleSurface.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "bcassim/Error.h"

namespace bcassim {

SurfaceSamples sampleVisibleSurface(const TriMesh& s, const Vec3& view, double coverage, int count,
                                    std::uint64_t seed) {
  if (!(coverage > 0.0 && coverage <= 1.0))
    throw InputError(fmt::format(
        "surface camera coverage {}; expected a fraction of the area in (0, 1]", coverage));
  if (count < 1)
    throw InputError(fmt::format("surface camera samples {}; expected at least 1", count));
  const Eigen::Index nf = s.F.rows();
  if (nf == 0) throw InputError("surface camera: the surface has no triangles");
  std::vector<double> area(static_cast<size_t>(nf)), facing(static_cast<size_t>(nf));
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Vec3 a = s.V.row(s.F(f, 0)), b = s.V.row(s.F(f, 1)), c = s.V.row(s.F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    area[f] = 0.5 * n.norm();
    facing[f] = n.norm() > 0.0 ? n.normalized().dot(view.normalized()) : -1.0;
  }
  std::vector<int> order(static_cast<size_t>(nf));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return facing[a] > facing[b]; });
  const double total = std::accumulate(area.begin(), area.end(), 0.0);
  std::vector<int> faces;
  std::vector<double> cumulative;
  double covered = 0.0;
  for (int f : order) {
    if (covered >= coverage * total) break;
    if (area[f] <= 0.0) continue;
    faces.push_back(f);
    covered += area[f];
    cumulative.push_back(covered);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SurfaceSamples out;
  out.areaFraction = covered / total;
  out.points.resize(count, 3);
  for (int i = 0; i < count; ++i) {
    const size_t k = static_cast<size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), unit(rng) * covered) -
        cumulative.begin());
    const int f = faces[std::min(k, faces.size() - 1)];
    double u = unit(rng), v = unit(rng);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    out.points.row(i) =
        (1.0 - u - v) * s.V.row(s.F(f, 0)) + u * s.V.row(s.F(f, 1)) + v * s.V.row(s.F(f, 2));
  }
  return out;
}

}  // namespace bcassim
