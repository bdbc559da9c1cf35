// A synthetic depth-camera recording of a partial organ surface (an RGB-D or stereo sensor):
// every frame a fresh random subset of points on the part of the truth's surface that faces the
// camera, with noise and a few outliers, in the camera's frame, without correspondences. The
// point-cloud variant of pipeline-tracked (thesis §5.3 with a surface instead of tackers). SI.
#pragma once
#include <vector>

#include "bcassim/experiments/tracked/SyntheticCamera.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/DetectionsCsv.h"

namespace bcassim {

struct SurfaceCameraOptions {
  double coverage = 0.3;     // fraction of the surface's area seen: the faces most turned to it
  int samples = 3000;        // points placed on that part (the truth carries them)
  int pointsPerFrame = 500;  // of those, drawn afresh every frame (a sensor's pixels move)
  double outliers = 0.01;    // fraction of each frame's points replaced by outliers
};

struct SurfaceRecording {
  std::vector<TimedPoints> frames;         // points in the camera frame, shuffled
  std::vector<std::vector<int>> sampleOf;  // per frame, per point: its sample, -1 outlier
  RigidTransform modelToCamera;            // the true pose of the camera frame
  int points = 0, outliers = 0;
};

// `truth`: the samples' tracks in the model frame (a truth run's markers.csv). The pose, noise
// and outliers' box margin are camera's (as recordTackers draws them, from camera.seed); every
// frame draws options.pointsPerFrame of the samples without replacement, then replaces a
// fraction options.outliers of them by points uniform in the frame's box grown by the margin.
// Throws InputError for options out of range or a truth frame with a missing sample.
SurfaceRecording recordSurface(const MarkerTracks& truth, const CameraOptions& camera,
                               const SurfaceCameraOptions& options);

}  // namespace bcassim
