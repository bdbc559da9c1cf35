// How well tracking kept the identities of synthetic tackers, measured against the recording's
// true source of every detection: switches, wrong labels, spurious detections given an id.
#pragma once
#include <vector>

namespace bcassim {

struct TrackingScore {
  int tracks = 0;               // confirmed tracks (ids)
  int tackersTracked = 0;       // tackers that are the main source of at least one track
  int labelled = 0;             // tacker detections given an id
  int unlabelled = 0;           // tacker detections left without one
  int wrongLabels = 0;          // labelled tacker detections of a track that is mainly another's
  int identitySwitches = 0;     // a tacker's consecutive labelled detections under different ids
  int spuriousLabelled = 0;     // spurious detections given an id
  std::vector<int> mainTacker;  // per track: the tacker most of its detections come from
};

// ids: per frame, per detection, the track id or -1 (TrackingResult::ids); tackerOf: the same
// shape, the true tacker (0 .. numTackers - 1) or -1 for a spurious detection. A track's main
// source is the tacker most of its detections come from (ties: the lower tacker).
TrackingScore scoreTracking(const std::vector<std::vector<int>>& ids,
                            const std::vector<std::vector<int>>& tackerOf, int numTackers);

}  // namespace bcassim
