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

// A curve with its band on a surface, as `atlas build` and `atlas transfer` leave them for
// ParaView and scripts/plot_atlas.py: surface.vtp/.obj, mean_curve.csv (x,y,z,sigma),
// band_lower.csv, band_upper.csv (x,y,z) and the three curves as .vtp polylines. Metres.
void writeCarriedCurveFiles(const std::string& dir, const TriMesh& surface, const CarriedCurve& c);

}  // namespace bcassim
