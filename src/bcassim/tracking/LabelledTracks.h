// The detections that tracking labelled, as marker tracks: frame by frame, the position of each
// id (NaN where the marker was not seen), the tracks CSV that `bcassim track` writes.
#pragma once
#include <vector>

#include "bcassim/io/CsvTracks.h"
#include "bcassim/tracking/MarkerTracker.h"

namespace bcassim {

// One frame per frame of `frames` with at least one labelled detection, at its time, with
// result.tracks.size() rows (row k: the detection labelled k there, else NaN). Frames the
// tracker skipped have no labelled detection, so the times increase.
MarkerTracks labelledTracks(const std::vector<DetectionFrame>& frames,
                            const TrackingResult& result);

// Writes `tracks` as time,marker,x,y,z rows (MarkerTrackWriter: NaN rows left out). Throws
// InputError when the file cannot be written.
void writeMarkerTracks(const std::string& path, const MarkerTracks& tracks);

}  // namespace bcassim
