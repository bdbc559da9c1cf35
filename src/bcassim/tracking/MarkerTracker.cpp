#include "bcassim/tracking/MarkerTracker.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {
namespace {

void requireOptions(const TrackerOptions& o) {
  auto positive = [](double value, const char* name, const char* unit) {
    if (!(value > 0.0) || !std::isfinite(value))
      throw InputError(
          fmt::format("tracker option {} is {} {}; expected a positive finite "
                      "number ({})",
                      name, value, unit, unit));
  };
  positive(o.gate, "gate", "m");
  positive(o.measurementNoise, "measurementNoise", "m");
  positive(o.accelerationNoise, "accelerationNoise", "m/s^2");
  if (o.confirmFrames < 1)
    throw InputError(fmt::format("tracker option confirmFrames is {}; expected at least 1 frame",
                                 o.confirmFrames));
  if (o.maxMissedFrames < 0)
    throw InputError(fmt::format("tracker option maxMissedFrames is {}; expected 0 or more frames",
                                 o.maxMissedFrames));
}

}  // namespace

MarkerTracker::MarkerTracker(const TrackerOptions& options) : options_(options) {
  requireOptions(options_);
}

Vec3 MarkerTracker::predict(const LiveTrack& track, double time) const {
  return options_.prediction == MotionPrediction::ConstantVelocity ? track.motion.predict(time)
                                                                   : track.lastSeen;
}

void MarkerTracker::pair(const std::vector<int>& candidates, const Eigen::MatrixX3d& points,
                         std::vector<char>& detectionFree, double time,
                         std::vector<int>& trackOfDetection) {
  std::vector<int> columns;
  for (int j = 0; j < static_cast<int>(detectionFree.size()); ++j)
    if (detectionFree[j]) columns.push_back(j);
  if (candidates.empty() || columns.empty()) return;
  Eigen::MatrixXd squaredDistances(candidates.size(), columns.size());
  for (size_t r = 0; r < candidates.size(); ++r) {
    const Vec3 predicted = predict(live_[candidates[r]], time);
    for (size_t c = 0; c < columns.size(); ++c)
      squaredDistances(r, c) = (points.row(columns[c]).transpose() - predicted).squaredNorm();
  }
  const Assignment a = matchWithinGate(squaredDistances, options_.gate, options_.assignment);
  for (size_t r = 0; r < candidates.size(); ++r) {
    const int c = a.columnOfRow[r];
    if (c < 0) continue;
    trackOfDetection[columns[c]] = candidates[r];
    detectionFree[columns[c]] = 0;
  }
}

std::vector<int> MarkerTracker::addFrame(const DetectionFrame& frame,
                                         std::vector<std::string>& report) {
  const int f = frameIndex_++;
  const double t = frame.time;
  const int n = static_cast<int>(frame.points.rows());
  std::vector<int> ids(n, -1);
  if (!std::isfinite(t)) {
    report.push_back(
        fmt::format("frame {}: time is {:g}; expected a finite time (s), frame skipped", f, t));
    return ids;
  }
  if (anyFrameAccepted_ && t <= lastTime_) {
    report.push_back(
        t == lastTime_
            ? fmt::format("frame {} (t = {:g} s): same time as the previous frame; frame skipped",
                          f, t)
            : fmt::format("frame {} (t = {:g} s): earlier than the previous frame (t = {:g} s); "
                          "frame skipped",
                          f, t, lastTime_));
    return ids;
  }
  anyFrameAccepted_ = true;
  lastTime_ = t;

  std::vector<char> detectionFree(n, 1);
  int usable = 0;
  for (int j = 0; j < n; ++j) {
    if (frame.points.row(j).allFinite()) {
      ++usable;
      continue;
    }
    detectionFree[j] = 0;
    report.push_back(fmt::format(
        "frame {} (t = {:g} s), detection {}: non-finite coordinate ({:g}, {:g}, {:g}); detection "
        "dropped",
        f, t, j, frame.points(j, 0), frame.points(j, 1), frame.points(j, 2)));
  }
  if (usable == 0)
    report.push_back(
        fmt::format("frame {} (t = {:g} s): no detections; tracks coast through it", f, t));

  // Confirmed tracks choose first, so a tentative track (maybe a spurious detection) never takes
  // a detection from a known marker.
  std::vector<int> confirmed, tentative;
  for (int k = 0; k < static_cast<int>(live_.size()); ++k)
    (live_[k].id >= 0 ? confirmed : tentative).push_back(k);
  std::vector<int> trackOfDetection(n, -1);
  pair(confirmed, frame.points, detectionFree, t, trackOfDetection);
  pair(tentative, frame.points, detectionFree, t, trackOfDetection);

  std::vector<char> seen(live_.size(), 0);
  for (int j = 0; j < n; ++j) {
    if (trackOfDetection[j] < 0) continue;
    LiveTrack& track = live_[trackOfDetection[j]];
    seen[trackOfDetection[j]] = 1;
    const Vec3 p = frame.points.row(j).transpose();
    track.motion.update(p, t);
    track.lastSeen = p;
    ++track.hits;
    track.misses = 0;
    track.frames.push_back(f);
    track.detections.push_back(j);
  }
  for (size_t k = 0; k < live_.size(); ++k)
    if (!seen[k]) {
      live_[k].hits = 0;
      ++live_[k].misses;
    }
  // Leftover detections start tentative tracks.
  for (int j = 0; j < n; ++j) {
    if (!detectionFree[j]) continue;
    const Vec3 p = frame.points.row(j).transpose();
    live_.push_back(
        {-1,
         ConstantVelocityModel(p, t, options_.measurementNoise, options_.accelerationNoise),
         p,
         1,
         0,
         {f},
         {j}});
  }
  std::erase_if(live_, [&](const LiveTrack& track) {
    return track.id < 0 ? track.misses > 0 : track.misses > options_.maxMissedFrames;
  });
  for (LiveTrack& track : live_) {
    if (track.id < 0 && track.hits >= options_.confirmFrames) {
      track.id = static_cast<int>(tracks_.size());
      tracks_.push_back({track.id, {}, {}});
    }
    if (track.id < 0 || track.misses > 0) continue;
    Track& out = tracks_[track.id];
    out.frames.insert(out.frames.end(), track.frames.begin(), track.frames.end());
    out.detections.insert(out.detections.end(), track.detections.begin(), track.detections.end());
    track.frames.clear();
    track.detections.clear();
    ids[out.detections.back()] = track.id;
  }
  return ids;
}

TrackingResult trackMarkers(const std::vector<DetectionFrame>& frames,
                            const TrackerOptions& options) {
  MarkerTracker tracker(options);
  TrackingResult result;
  result.ids.reserve(frames.size());
  for (const DetectionFrame& frame : frames)
    result.ids.push_back(tracker.addFrame(frame, result.report));
  result.tracks = tracker.tracks();
  for (const Track& track : result.tracks)
    for (size_t k = 0; k < track.frames.size(); ++k)
      result.ids[track.frames[k]][track.detections[k]] = track.id;
  return result;
}

}  // namespace bcassim
