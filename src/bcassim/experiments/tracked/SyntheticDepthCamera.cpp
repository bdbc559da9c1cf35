#include "bcassim/experiments/tracked/SyntheticDepthCamera.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>
#include <random>

#include "bcassim/Error.h"

namespace bcassim {

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
