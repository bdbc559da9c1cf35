#include "bcassim/experiments/tracked/TrackingScore.h"

#include <algorithm>
#include <stdexcept>

namespace bcassim {

TrackingScore scoreTracking(const std::vector<std::vector<int>>& ids,
                            const std::vector<std::vector<int>>& tackerOf, int numTackers) {
  if (ids.size() != tackerOf.size())
    throw std::invalid_argument("scoreTracking: ids and sources differ in frames");
  TrackingScore s;
  int numTracks = 0;
  for (const auto& frame : ids)
    for (int id : frame) numTracks = std::max(numTracks, id + 1);
  s.tracks = numTracks;
  // counts(track, tacker): detections of the tacker labelled with the track.
  std::vector<std::vector<int>> counts(numTracks, std::vector<int>(numTackers, 0));
  std::vector<int> lastId(numTackers, -1);
  for (size_t f = 0; f < ids.size(); ++f) {
    if (ids[f].size() != tackerOf[f].size())
      throw std::invalid_argument("scoreTracking: ids and sources differ in detections");
    for (size_t j = 0; j < ids[f].size(); ++j) {
      const int id = ids[f][j], tacker = tackerOf[f][j];
      if (tacker < 0) {
        s.spuriousLabelled += id >= 0;
        continue;
      }
      if (id < 0) {
        ++s.unlabelled;
        continue;
      }
      ++s.labelled;
      ++counts[id][tacker];
      if (lastId[tacker] >= 0 && lastId[tacker] != id) ++s.identitySwitches;
      lastId[tacker] = id;
    }
  }
  std::vector<char> tracked(numTackers, 0);
  s.mainTacker.assign(numTracks, -1);
  for (int t = 0; t < numTracks; ++t) {
    const auto main = std::max_element(counts[t].begin(), counts[t].end());
    if (main == counts[t].end() || *main == 0) continue;
    s.mainTacker[t] = static_cast<int>(main - counts[t].begin());
    tracked[main - counts[t].begin()] = 1;
    for (int c : counts[t]) s.wrongLabels += c;
    s.wrongLabels -= *main;
  }
  s.tackersTracked = static_cast<int>(std::count(tracked.begin(), tracked.end(), 1));
  return s;
}

}  // namespace bcassim
