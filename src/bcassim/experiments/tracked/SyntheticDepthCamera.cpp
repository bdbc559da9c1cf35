#include "bcassim/experiments/tracked/SyntheticDepthCamera.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <random>

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

SurfaceRecording recordSurface(const MarkerTracks& truth, const CameraOptions& camera,
                               const SurfaceCameraOptions& o) {
  requireCameraOptions(camera);
  if (o.pointsPerFrame < 1 || !(o.outliers >= 0.0 && o.outliers < 1.0))
    throw InputError(
        fmt::format("surface camera pointsPerFrame {}, outliers {}; expected at least 1 and a "
                    "fraction in [0, 1)",
                    o.pointsPerFrame, o.outliers));
  if (truth.frames.empty()) throw InputError("surface camera: no truth frames to record");
  for (size_t f = 0; f < truth.frames.size(); ++f)
    if (!truth.frames[f].allFinite())
      throw InputError(fmt::format(
          "surface camera: truth frame at t = {} s misses a sample; expected every sample in "
          "every frame",
          truth.times[f]));
  std::mt19937_64 rng(camera.seed);
  SurfaceRecording rec;
  rec.modelToCamera =
      drawCameraPose(truth.frames.front().colwise().mean().transpose(), camera, rng);
  const int samples = truth.numMarkers;
  const int drawn = std::min(o.pointsPerFrame, samples);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<int> pool(static_cast<size_t>(samples));
  for (size_t f = 0; f < truth.frames.size(); ++f) {
    const Eigen::MatrixX3d& P = truth.frames[f];
    const Vec3 low = P.colwise().minCoeff().transpose().array() - camera.spuriousMargin;
    const Vec3 high = P.colwise().maxCoeff().transpose().array() + camera.spuriousMargin;
    std::iota(pool.begin(), pool.end(), 0);
    std::shuffle(pool.begin(), pool.end(), rng);  // the first `drawn` are this frame's
    TimedPoints frame{truth.times[f], Eigen::MatrixX3d(drawn, 3)};
    std::vector<int> sampleOf(static_cast<size_t>(drawn));
    for (int i = 0; i < drawn; ++i) {
      Vec3 p;
      if (uniform(rng) < o.outliers) {
        const Vec3 u(uniform(rng), uniform(rng), uniform(rng));
        p = low + u.cwiseProduct(high - low);
        sampleOf[static_cast<size_t>(i)] = -1;
        ++rec.outliers;
      } else {
        const int k = pool[static_cast<size_t>(i)];
        p = P.row(k).transpose() + camera.noise * Vec3(noise(rng), noise(rng), noise(rng));
        sampleOf[static_cast<size_t>(i)] = k;
      }
      frame.points.row(i) = rec.modelToCamera.apply(p.transpose());
    }
    rec.points += drawn;
    rec.frames.push_back(std::move(frame));
    rec.sampleOf.push_back(std::move(sampleOf));
  }
  return rec;
}

}  // namespace bcassim
