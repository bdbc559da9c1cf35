// Synthetic tacker detections for the tracker tests: markers on a breathing, deforming dome, two
// pairs whose trajectories cross, Gaussian noise, dropouts, spurious detections, shuffled rows.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/tracking/MarkerTracker.h"

namespace bcassim::test {

struct SyntheticMarkerOptions {
  int frames = 3000;
  double frameRate = 30.0;      // Hz
  double noise = 0.001;         // m, standard deviation per coordinate (1.7 mm in 3-D)
  double dropout = 0.2;         // probability that a marker is missed in a frame
  double spurious = 0.01;       // spurious detections per true detection
  double passDistance = 0.005;  // m, closest approach of the crossing pairs
  unsigned seed = 1;
};

struct SyntheticMarkers {
  std::vector<DetectionFrame> frames;
  std::vector<std::vector<int>> truth;  // per frame, per detection: the marker, -1 for spurious
  int numMarkers = 0;
};

constexpr int kSyntheticMarkers = 14;

// Marker k at time t (s), m. Markers 0-9: a 5 x 2 grid, 3 cm by 8 cm, on a dome, moved by a
// smooth deformation (amplitudes 6-10 mm, 0.2-0.33 Hz). Markers 10/11 oscillate head-on past
// each other along x, 12/13 cross at right angles (x and y), +-15 mm at 0.4 Hz, passing
// `passDistance` (m) apart in z, as trajectories crossing in a camera's image: 0.8 crossings per
// second per pair, at up to 75 mm/s relative speed.
inline Vec3 syntheticMarkerPosition(int k, double t, double passDistance) {
  constexpr double pi = std::numbers::pi;
  Vec3 rest;
  if (k < 10)
    rest << -0.06 + 0.03 * (k % 5), k < 5 ? -0.04 : 0.04, 0.0;
  else
    rest << (k < 12 ? -0.045 : 0.045), 0.0, 0.0;
  rest.z() = 0.05 - 4.0 * (rest.x() * rest.x() + rest.y() * rest.y());
  const Vec3 deformation(0.008 * std::sin(2 * pi * 0.2 * t + 20 * rest.x()),
                         0.006 * std::sin(2 * pi * 0.27 * t + 25 * rest.y() + 1),
                         0.010 * std::sin(2 * pi * 0.33 * t + 10 * (rest.x() + rest.y())));
  const double s = 0.015 * std::sin(2 * pi * 0.4 * t);
  Vec3 crossing = Vec3::Zero();
  if (k == 10) crossing.x() = s;
  if (k == 11) crossing << -s, 0.0, passDistance;
  if (k == 12) crossing.x() = s;
  if (k == 13) crossing << 0.0, s, passDistance;
  return rest + deformation + crossing;
}

inline SyntheticMarkers makeSyntheticMarkers(const SyntheticMarkerOptions& o) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> noise(0.0, o.noise);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SyntheticMarkers out;
  out.numMarkers = kSyntheticMarkers;
  for (int f = 0; f < o.frames; ++f) {
    const double t = f / o.frameRate;
    std::vector<std::pair<Vec3, int>> detections;
    for (int k = 0; k < kSyntheticMarkers; ++k) {
      if (unit(rng) < o.dropout) continue;
      detections.push_back(
          {syntheticMarkerPosition(k, t, o.passDistance) + Vec3(noise(rng), noise(rng), noise(rng)),
           k});
      // Spurious detections anywhere in the markers' region (12 x 10 x 6 cm, with margins).
      if (unit(rng) < o.spurious)
        detections.push_back(
            {Vec3(-0.09 + 0.18 * unit(rng), -0.07 + 0.14 * unit(rng), -0.01 + 0.08 * unit(rng)),
             -1});
    }
    std::shuffle(detections.begin(), detections.end(), rng);
    DetectionFrame frame{t, Eigen::MatrixX3d(detections.size(), 3)};
    std::vector<int> truth;
    for (size_t j = 0; j < detections.size(); ++j) {
      frame.points.row(j) = detections[j].first.transpose();
      truth.push_back(detections[j].second);
    }
    out.frames.push_back(std::move(frame));
    out.truth.push_back(std::move(truth));
  }
  return out;
}

// Identity switches (as in the CLEAR-MOT metrics): each time a marker's detection is labelled
// with another id than the one it last had. Unlabelled detections do not count.
inline int countIdentitySwitches(const SyntheticMarkers& data, const TrackingResult& result) {
  std::vector<int> lastId(data.numMarkers, -1);
  int switches = 0;
  for (size_t f = 0; f < data.frames.size(); ++f)
    for (size_t j = 0; j < data.truth[f].size(); ++j) {
      const int marker = data.truth[f][j], id = result.ids[f][j];
      if (marker < 0 || id < 0) continue;
      if (lastId[marker] >= 0 && lastId[marker] != id) ++switches;
      lastId[marker] = id;
    }
  return switches;
}

}  // namespace bcassim::test
