// A ligament atlas on disk (the output of `bcassim atlas build`, the input of `atlas transfer`):
// a folder with template.obj, planes.csv, curve.csv (barycentric coordinates on the template)
// and carried_curves.csv. Metres.
#pragma once
#include <string>

#include "bcassim/atlas/LigamentAtlas.h"

namespace bcassim {

// Creates the folder if missing. Throws InputError when a file cannot be written.
void writeLigamentAtlas(const std::string& dir, const LigamentAtlas& atlas);

// Throws InputError naming the file and what was expected.
LigamentAtlas readLigamentAtlas(const std::string& dir);

}  // namespace bcassim
