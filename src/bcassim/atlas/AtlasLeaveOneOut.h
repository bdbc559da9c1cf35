// Leave-one-out validation of the ligament atlas (thesis §5.2, Table 5.1): for each held-out organ,
// the curve statistics of all the others are transferred to it and compared with its expert curve.
#pragma once
#include <vector>

#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/LigamentAtlas.h"

namespace bcassim {

struct LeaveOneOutOptions {
  LigamentAtlasOptions atlas;  // registration and planes; frechetMean is ignored (see below)
  int templateSubject = 0;     // the fixed template (never held out)
  std::vector<int> heldOut;    // subjects to hold out; empty: every subject but the template
};

struct LeaveOneOutFold {
  int subject = -1;
  int atlasPoints = 0;     // mean-curve points of this fold's atlas
  CurveDistance distance;  // transferred mean curve vs the expert curve (m)
  CurveDistance rigidOnly;  // same with the template only aligned rigidly (no LDDMM), for contrast
  CurveDistance median;     // LDDMM, per-plane geometric median instead of options' centre
};

struct LeaveOneOutResult {
  std::vector<LeaveOneOutFold> folds;
  std::vector<double> alignmentRms;         // per subject (m)
  std::vector<double> dataRatio;            // final / initial data term of template -> subject
  std::vector<double> registrationSeconds;  // per subject
};

// The template subject (centred on its bounding box) is registered once onto every subject after
// rigid multi-start alignment; subject i's curve is carried onto the template through that
// registration. Fold h builds the curve statistics from every carried curve but h's and carries
// the mean curve back onto subject h through the same template -> h registration, which never
// sees h's curve. With a fixed template this costs one registration per subject instead of one
// atlas per fold (the Fréchet-mean template of buildLigamentAtlas would differ per fold).
// Throws InputError on fewer than 3 subjects or bad indices.
LeaveOneOutResult leaveOneOut(const std::vector<AtlasSubject>& subjects,
                              const LeaveOneOutOptions& options = {}, const AtlasLog& log = {});

}  // namespace bcassim
