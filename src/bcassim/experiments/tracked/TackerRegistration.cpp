#include "bcassim/experiments/tracked/TackerRegistration.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {

TackerRegistration registerTackers(const MarkerTracks& cameraTracks, const TriMesh& surface,
                                   const TackerRegistrationOptions& o) {
  if (o.frames < 1)
    throw InputError(
        fmt::format("tacker registration over {} frames; expected at least 1", o.frames));
  const int numTracks = cameraTracks.numMarkers;
  const size_t window = std::min(cameraTracks.frames.size(), static_cast<size_t>(o.frames));
  Eigen::MatrixX3d sum = Eigen::MatrixX3d::Zero(numTracks, 3);
  std::vector<int> seen(numTracks, 0);
  for (size_t f = 0; f < window; ++f)
    for (int m = 0; m < numTracks; ++m)
      if (cameraTracks.frames[f].row(m).allFinite()) {
        sum.row(m) += cameraTracks.frames[f].row(m);
        ++seen[m];
      }
  TackerRegistration r;
  std::vector<int> markerOfTrack(numTracks, -1);
  for (int m = 0; m < numTracks; ++m) {
    if (seen[m] == 0) {
      r.droppedTracks.push_back(m);
      continue;
    }
    markerOfTrack[m] = static_cast<int>(r.trackOfMarker.size());
    r.trackOfMarker.push_back(m);
  }
  const auto numMarkers = static_cast<Eigen::Index>(r.trackOfMarker.size());
  if (numMarkers < 6)
    throw InputError(fmt::format(
        "tacker registration: {} tracks seen in the first {} frames; expected at least 6",
        numMarkers, window));
  Eigen::MatrixX3d mean(numMarkers, 3);
  for (Eigen::Index k = 0; k < numMarkers; ++k)
    mean.row(k) = sum.row(r.trackOfMarker[k]) / seen[r.trackOfMarker[k]];

  r.icp = registerPointsToSurface(mean, surface, o.icp);
  r.registered = r.icp.transform.apply(mean);
  const SurfaceLocator locator(surface);
  r.markersAtRest.resize(numMarkers, 3);
  for (Eigen::Index k = 0; k < numMarkers; ++k)
    r.markersAtRest.row(k) = locator.closest(r.registered.row(k).transpose()).point.transpose();

  r.modelTracks.times = cameraTracks.times;
  r.modelTracks.numMarkers = static_cast<int>(numMarkers);
  for (const Eigen::MatrixX3d& frame : cameraTracks.frames) {
    Eigen::MatrixX3d moved =
        Eigen::MatrixX3d::Constant(numMarkers, 3, std::numeric_limits<double>::quiet_NaN());
    const Eigen::MatrixX3d all = r.icp.transform.apply(frame);  // NaN rows stay NaN
    for (Eigen::Index k = 0; k < numMarkers; ++k) moved.row(k) = all.row(r.trackOfMarker[k]);
    r.modelTracks.frames.push_back(std::move(moved));
  }
  return r;
}

}  // namespace bcassim
