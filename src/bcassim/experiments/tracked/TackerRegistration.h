// Tracked tackers onto the estimation model (thesis §5.3: "the registration was based on the
// superficial tackers ... iterative closest point"): their mean positions over the first frames
// registered rigidly to the model's surface by ICP, then each tacker a labelled marker on it.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/io/CsvTracks.h"
#include "bcassim/mesh/TriMesh.h"
#include "bcassim/tracking/SurfaceRegistration.h"

namespace bcassim {

struct TackerRegistrationOptions {
  // First frames of the tracks averaged per track (the organ barely moves yet; the mean lowers
  // the noise): the points registered. A track not seen in them is not a marker.
  int frames = 5;
  SurfaceRegistrationOptions icp;  // its `initial` is the first guess, camera -> model
};

struct TackerRegistration {
  SurfaceRegistration icp;         // camera frame -> model frame, RMS (m), overlap
  std::vector<int> trackOfMarker;  // marker k is track trackOfMarker[k]
  Eigen::MatrixX3d registered;     // #markers by 3: the mean positions moved to the model, m
  Eigen::MatrixX3d markersAtRest;  // #markers by 3: those projected onto the surface, m
  MarkerTracks modelTracks;  // every frame of the tracks moved to the model, markers renumbered
  std::vector<int> droppedTracks;  // tracks without a detection in the first frames
};

// cameraTracks: labelled tracks in the camera frame (tracks.csv of `bcassim track`); surface:
// the model's boundary at rest (m). Throws InputError when fewer than 6 tracks are seen in the
// first frames, or as registerPointsToSurface.
TackerRegistration registerTackers(const MarkerTracks& cameraTracks, const TriMesh& surface,
                                   const TackerRegistrationOptions& options);

}  // namespace bcassim
