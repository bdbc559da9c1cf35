// A folder of annotated livers (NAME.obj surfaces with NAME.eseg edge labels, as the shared CT
// livers come) read as atlas subjects: the surface and its labelled attachment curve, in metres.
#pragma once
#include <string>
#include <vector>

#include "bcassim/atlas/LigamentAtlas.h"

namespace bcassim {

struct LiverFolder {
  std::vector<AtlasSubject> subjects;  // surfaces and attachment curves, coordinates * scale
  std::vector<std::string> skipped;    // "name: reason", one per liver that could not be used
};

// Every NAME.obj of dir that has a NAME.eseg beside it, sorted by name, with the curve of edges
// labelled `label` (2: falciform), that label's edges (band) and the edges labelled ridgeLabel
// (3: the liver's anterior-inferior border; none is fine). scale: factor to metres (1e-3 for the
// shared livers).
// Unusable livers are skipped with their reason. Throws InputError when dir is not a folder.
LiverFolder readAnnotatedLivers(const std::string& dir, int label = 2, double scale = 1e-3,
                                int ridgeLabel = 3);

}  // namespace bcassim
