// The liver experiment's scenes as files for the user (truth.yaml, estimate.yaml,
// baseline.yaml), written from the same values as the scenes built in code (LiverScenes.h), so
// that loadScene on a file gives that scene. The pipeline never reads them back.
#pragma once

#include "bcassim/experiments/liver/LiverScenes.h"

namespace bcassim {

// Writes spec.dir/truth.yaml, estimate.yaml and baseline.yaml (numbers at 17 significant digits,
// units in comments). They name the files prepareLiverScenario writes beside them (fine.vtu,
// coarse.vtu, curve.csv, markers.csv, validation.csv, tumours.csv) and the truth run's tracks
// (truth/markers.csv, truth/validation.csv). Throws InputError when a file cannot be written.
void writeLiverSceneFiles(const LiverSceneSpec& spec);

}  // namespace bcassim
