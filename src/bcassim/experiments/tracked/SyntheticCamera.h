// A synthetic intra-operative recording of tackers (thesis §5.3, Fig. 5.12): the truth's tacker
// positions as a camera would give them, in its own frame, with noise, dropouts and spurious
// detections, in no order and without ids. Metres, seconds.
#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/DetectionsCsv.h"
#include "bcassim/mesh/RigidTransform.h"

namespace bcassim {

struct CameraOptions {
  double noise = 0.001;    // m, standard deviation of each coordinate of a detection
  double dropout = 0.2;    // probability that a tacker goes undetected in a frame
  double spurious = 0.01;  // probability, per tacker and frame, of one spurious detection as well
  // The camera frame: rotated by angleDegrees about a random axis through the tackers' centroid
  // at rest and shifted by `offset` in a random direction, both drawn from the seed.
  double offset = 0.1;  // m
  double angleDegrees = 20.0;
  // Spurious detections fall uniformly in the frame's tackers' bounding box grown by this.
  double spuriousMargin = 0.03;  // m
  std::uint64_t seed = 1;
};

struct CameraRecording {
  std::vector<TimedPoints> frames;         // detections in the camera frame, shuffled
  std::vector<std::vector<int>> tackerOf;  // per frame, per detection: its tacker, -1 spurious
  RigidTransform modelToCamera;            // the true pose of the camera frame
  int detections = 0, spuriousDetections = 0;
};

// Throws InputError naming the first option out of range.
void requireCameraOptions(const CameraOptions& options);

// The camera frame: rotated by options.angleDegrees about a random axis through `centre`, then
// shifted by options.offset in a random direction; the two directions drawn from `rng` in that
// order.
RigidTransform drawCameraPose(const Vec3& centre, const CameraOptions& options,
                              std::mt19937_64& rng);

// `truth`: the tackers' tracks in the model frame (a truth run's markers.csv), each frame with
// every tacker. One camera frame per truth frame, at its time. Deterministic for a seed. Throws
// InputError for options out of range or a truth frame with a missing tacker.
CameraRecording recordTackers(const MarkerTracks& truth, const CameraOptions& options);

}  // namespace bcassim
