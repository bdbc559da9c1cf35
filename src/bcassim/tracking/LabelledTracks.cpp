#include "bcassim/tracking/LabelledTracks.h"

#include <limits>
#include <stdexcept>

namespace bcassim {

MarkerTracks labelledTracks(const std::vector<DetectionFrame>& frames,
                            const TrackingResult& result) {
  if (result.ids.size() != frames.size())
    throw std::invalid_argument("labelledTracks: the result is of other frames");
  MarkerTracks tracks;
  tracks.numMarkers = static_cast<int>(result.tracks.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    Eigen::MatrixX3d positions =
        Eigen::MatrixX3d::Constant(tracks.numMarkers, 3, std::numeric_limits<double>::quiet_NaN());
    bool any = false;
    for (Eigen::Index j = 0; j < frames[f].points.rows(); ++j) {
      const int id = result.ids[f][static_cast<size_t>(j)];
      if (id < 0) continue;
      positions.row(id) = frames[f].points.row(j);
      any = true;
    }
    if (!any) continue;
    tracks.times.push_back(frames[f].time);
    tracks.frames.push_back(std::move(positions));
  }
  return tracks;
}

void writeMarkerTracks(const std::string& path, const MarkerTracks& tracks) {
  MarkerTrackWriter writer(path);
  for (size_t f = 0; f < tracks.frames.size(); ++f) writer.write(tracks.times[f], tracks.frames[f]);
}

}  // namespace bcassim
