#include "bcassim/experiments/tracked/SyntheticCamera.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numbers>
#include <numeric>
#include <random>

#include "bcassim/Error.h"
#include "bcassim/Types.h"

namespace bcassim {
namespace {

Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Vec3 v;
  do v = Vec3(normal(rng), normal(rng), normal(rng));
  while (v.norm() < 1e-6);
  return v.normalized();
}

}  // namespace

void requireCameraOptions(const CameraOptions& o) {
  auto check = [](bool ok, const char* name, double value, const char* expected) {
    if (!ok)
      throw InputError(fmt::format("camera option {} is {}; expected {}", name, value, expected));
  };
  check(o.noise >= 0.0, "noise", o.noise, "a standard deviation >= 0 (m)");
  check(o.dropout >= 0.0 && o.dropout < 1.0, "dropout", o.dropout, "a probability in [0, 1)");
  check(o.spurious >= 0.0 && o.spurious <= 1.0, "spurious", o.spurious, "a probability in [0, 1]");
  check(o.offset >= 0.0, "offset", o.offset, "a distance >= 0 (m)");
  check(o.spuriousMargin >= 0.0, "spuriousMargin", o.spuriousMargin, "a distance >= 0 (m)");
}

RigidTransform drawCameraPose(const Vec3& centre, const CameraOptions& o, std::mt19937_64& rng) {
  RigidTransform pose;
  pose.rotation = Eigen::AngleAxisd(o.angleDegrees * std::numbers::pi / 180.0, randomUnit(rng))
                      .toRotationMatrix();
  pose.translation = centre - pose.rotation * centre + o.offset * randomUnit(rng);
  return pose;
}

CameraRecording recordTackers(const MarkerTracks& truth, const CameraOptions& o) {
  requireCameraOptions(o);
  if (truth.frames.empty()) throw InputError("camera: no truth frames to record");
  for (size_t f = 0; f < truth.frames.size(); ++f)
    if (!truth.frames[f].allFinite())
      throw InputError(
          fmt::format("camera: truth frame at t = {} s misses a tacker; expected "
                      "every tacker in every frame",
                      truth.times[f]));
  std::mt19937_64 rng(o.seed);
  CameraRecording rec;
  rec.modelToCamera = drawCameraPose(truth.frames.front().colwise().mean().transpose(), o, rng);
  const Eigen::Matrix3d& R = rec.modelToCamera.rotation;

  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (size_t f = 0; f < truth.frames.size(); ++f) {
    const Eigen::MatrixX3d& tackers = truth.frames[f];
    const Vec3 low = tackers.colwise().minCoeff().transpose().array() - o.spuriousMargin;
    const Vec3 high = tackers.colwise().maxCoeff().transpose().array() + o.spuriousMargin;
    std::vector<Vec3> points;
    std::vector<int> source;
    for (Eigen::Index k = 0; k < tackers.rows(); ++k) {
      if (uniform(rng) >= o.dropout) {
        points.push_back(tackers.row(k).transpose() +
                         o.noise * Vec3(noise(rng), noise(rng), noise(rng)));
        source.push_back(static_cast<int>(k));
      }
      if (uniform(rng) < o.spurious) {
        const Vec3 u(uniform(rng), uniform(rng), uniform(rng));
        points.push_back(low + u.cwiseProduct(high - low));
        source.push_back(-1);
        ++rec.spuriousDetections;
      }
    }
    std::vector<int> order(points.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    TimedPoints frame{truth.times[f],
                      Eigen::MatrixX3d(static_cast<Eigen::Index>(points.size()), 3)};
    std::vector<int> tackerOf(points.size());
    for (size_t i = 0; i < order.size(); ++i) {
      frame.points.row(static_cast<Eigen::Index>(i)) =
          (R * points[order[i]]).transpose() + rec.modelToCamera.translation.transpose();
      tackerOf[i] = source[order[i]];
    }
    rec.detections += static_cast<int>(points.size());
    rec.frames.push_back(std::move(frame));
    rec.tackerOf.push_back(std::move(tackerOf));
  }
  return rec;
}

}  // namespace bcassim
