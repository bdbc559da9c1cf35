// Internal to the io module: legacy VTK files (.vtk) read by a bounded parser of our own instead of
// VTK's reader, which overflows its heap on a wrong CELLS row and allocates whatever a count says.
#pragma once
#include <string>

#include "bcassim/io/VtkDataset.h"

namespace bcassim::io {

// Reads the legacy VTK file `path` (ASCII or BINARY; file versions up to 4.2 with "CELLS n size"
// rows, 5.x with OFFSETS and CONNECTIVITY) holding the dataset kind `expected`. Every count is
// checked against the bytes left before anything is allocated for it, every point must be finite,
// every point id in range, and every unstructured-grid cell's point count must fit its type. Cell
// data arrays are kept as VTK's reader keeps them (the first of each attribute kind, every FIELD
// array); point data are checked and dropped. Throws InputError naming the file and the line
// (ASCII) or byte offset (BINARY) and what was expected, e.g. "cube.vtk:12: cell 3 has 5 point ids
// but its count says 4".
VtkDataset readLegacyVtk(const std::string& path, VtkDataset::Kind expected);

}  // namespace bcassim::io
