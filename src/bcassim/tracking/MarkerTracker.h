// Identities of unlabelled marker detections over frames (thesis §5.3: tackers seen by a camera):
// predicted positions, gated assignment, confirmation of new markers, coasting through dropouts.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/tracking/ConstantVelocityModel.h"
#include "bcassim/tracking/GatedMatching.h"

namespace bcassim {

// One camera frame: the time and the detected points, in no particular order.
struct DetectionFrame {
  double time = 0.0;        // s
  Eigen::MatrixX3d points;  // #detections by 3, m
};

enum class MotionPrediction {
  ConstantVelocity,  // a Kalman filter per track (ConstantVelocityModel.h)
  LastPosition,      // where the marker was last seen, as the thesis' frame-to-frame matching
};

struct TrackerOptions {
  AssignmentMethod assignment = AssignmentMethod::Optimal;
  MotionPrediction prediction = MotionPrediction::ConstantVelocity;
  double gate = 0.01;     // m: a detection farther than this from a track's prediction is not its
  int confirmFrames = 3;  // consecutive frames a new marker is seen in before it gets an id
  int maxMissedFrames = 10;  // a marker unseen for more frames than this loses its track and id
  double measurementNoise = 0.001;  // m, standard deviation of a detection's coordinates
  // m/s^2, standard deviation of the markers' unmodelled acceleration: larger follows abrupt
  // changes of motion sooner, at the price of noisier predictions.
  double accelerationNoise = 0.1;
};

// A confirmed marker: its id and where it was detected.
struct Track {
  int id = -1;                  // 0, 1, ... in order of confirmation
  std::vector<int> frames;      // indices of the frames it was detected in, increasing
  std::vector<int> detections;  // its row in each of those frames' points
};

// Frame by frame: each frame's detections are first paired with the confirmed tracks (those seen
// within maxMissedFrames), then the rest with the tentative ones; detections left over start
// tentative tracks. A tentative track seen in confirmFrames consecutive frames is confirmed and
// gets the next id; one missed once is dropped (a spurious detection never gets an id). A
// confirmed track unseen for more than maxMissedFrames frames ends; its id is never reused.
//
// Bad input is reported, one line per problem, and the tracker goes on where it can:
// - a frame whose time is not finite, or not after the previous accepted frame (out of order or
//   repeated): the frame is skipped, its detections get no id, no track ages;
// - a detection with a non-finite coordinate: that detection is dropped (no id), the rest of its
//   frame is used;
// - a frame without (finite) detections: every track coasts through it, one missed frame.
class MarkerTracker {
 public:
  // Throws InputError naming the option when one is out of range.
  explicit MarkerTracker(const TrackerOptions& options = {});

  // Labels the next frame: the id of each detection (row of frame.points), or -1 for a detection
  // without a confirmed track yet. Appends one line per input problem to `report`, e.g.
  // "frame 7 (t = 0.23 s): no detections; tracks coast through it".
  std::vector<int> addFrame(const DetectionFrame& frame, std::vector<std::string>& report);

  // Confirmed tracks so far, tracks()[k].id == k, including the detections that were seen while
  // the track was still tentative.
  const std::vector<Track>& tracks() const { return tracks_; }

 private:
  struct LiveTrack {
    int id = -1;  // -1 while tentative
    ConstantVelocityModel motion;
    Vec3 lastSeen;   // m, the last detection
    int hits = 0;    // consecutive frames seen
    int misses = 0;  // consecutive frames missed
    std::vector<int> frames, detections;
  };
  Vec3 predict(const LiveTrack& track, double time) const;
  // Pairs tracks[candidates] with points[free detections]; marks the detections paired.
  void pair(const std::vector<int>& candidates, const Eigen::MatrixX3d& points,
            std::vector<char>& detectionFree, double time, std::vector<int>& trackOfDetection);

  TrackerOptions options_;
  std::vector<LiveTrack> live_;
  std::vector<Track> tracks_;
  int frameIndex_ = 0;
  bool anyFrameAccepted_ = false;
  double lastTime_ = 0.0;  // s, of the last accepted frame
};

struct TrackingResult {
  std::vector<std::vector<int>> ids;  // per frame, per detection: its track's id, or -1
  std::vector<Track> tracks;          // confirmed tracks, tracks[k].id == k
  std::vector<std::string> report;    // one line per input problem, in frame order
};

// All frames at once (the order of the vector is the order of arrival). Unlike addFrame, the
// detections seen while a track was tentative get its id too.
TrackingResult trackMarkers(const std::vector<DetectionFrame>& frames,
                            const TrackerOptions& options = {});

}  // namespace bcassim
