// Internal to the io module: VTK XML files (.vtu, .vtp) read by a bounded reader of our own instead
// of VTK's, which crashes on integers beyond 32 bits and hangs on huge component counts.
#pragma once
#include <string>

#include "bcassim/io/VtkDataset.h"

namespace bcassim::io {

// Reads the VTK XML file `path` holding one piece of the dataset kind `expected` (.vtu unstructured
// grid or .vtp poly data): data arrays in ascii, base64 binary or appended (raw or base64) form,
// uncompressed or compressed by zlib, LZ4 or LZMA, with 32- or 64-bit headers in either byte order.
// Counts and components are checked against their limits and the data actually present before
// anything is allocated; every point must be finite, every offset in order, every point id in
// range and every unstructured-grid cell's point count must fit its type. Cell data arrays are
// kept; point data are not read. Throws InputError naming the file, the line and the element, e.g.
// "liver.vtu:3: <Piece>: NumberOfPoints="4294967297"; expected an integer from 0 to 2147483647".
VtkDataset readVtkXml(const std::string& path, VtkDataset::Kind expected);

}  // namespace bcassim::io
