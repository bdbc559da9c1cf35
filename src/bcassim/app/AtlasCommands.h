// The `bcassim atlas` commands (thesis §4.3, §5.2): distance, register, build, transfer; and the
// reader of the annotated liver folder that `atlas build` and the leave-one-out driver share.
#pragma once
#include <string>
#include <vector>

#include "bcassim/atlas/LigamentAtlas.h"

namespace CLI {
class App;
}

namespace bcassim {

// Adds `atlas` and its subcommands to app; each runs from its CLI11 callback, ends the parse
// with exit code 0 on success and throws InputError / NumericalError on failure.
void addAtlasCommands(CLI::App& app);

struct LiverFolder {
  std::vector<AtlasSubject> subjects;  // surfaces and attachment curves, coordinates * scale
  std::vector<std::string> skipped;    // "name: reason", one per liver that could not be used
};

// Every NAME.obj of dir that has a NAME.eseg beside it, sorted by name, with the curve of edges
// labelled `label` (2: falciform). scale: factor to metres (1e-3 for the shared livers).
// Unusable livers are skipped with their reason. Throws InputError when dir is not a folder.
LiverFolder readAnnotatedLivers(const std::string& dir, int label = 2, double scale = 1e-3);

}  // namespace bcassim
