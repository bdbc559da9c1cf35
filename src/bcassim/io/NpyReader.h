// Reading NumPy .npy arrays (format 1.0, 2.0, 3.0; either byte order; C or Fortran order) with
// every size checked against the file's length before anything is allocated.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace bcassim {

struct NpyArray {
  std::vector<std::int64_t> shape;     // e.g. {500, 3}; empty for a 0-d array
  std::string dtype;                   // as the header writes it, e.g. "<f8"
  std::vector<double> values;          // every element in C order, as a double
  std::vector<std::int64_t> integers;  // the same elements exactly, for integer and bool dtypes
                                       // (empty for float dtypes)
  bool isInteger() const { return dtype.size() == 3 && dtype[1] != 'f'; }
};

// dtypes read: f4, f8, i1, i2, i4, i8, u1, u2, u4, u8 and b1 (bool), little- or big-endian
// ('<', '>'; '|' for one byte). A Fortran-order array (np.save of a transposed array) is returned
// in C order. Throws InputError with one line naming the file and what was expected, e.g. "a.npy:
// data of 40 bytes; expected 48 bytes for shape (2, 3) of <f8": a wrong magic string or version,
// a truncated or malformed header, another dtype (complex, structured, strings, objects), data
// shorter or longer than the shape says, a u8 value above 2^63 - 1.
NpyArray readNpy(const std::string& path);

// A shape as NumPy prints it: "(50, 3046, 3)", "(106,)", "()".
std::string formatNpyShape(const std::vector<std::int64_t>& shape);

// The multi-index of element `flat` (C order) of an array of `shape`, e.g. "(3, 1)" or "(7,)".
std::string formatNpyIndex(const std::vector<std::int64_t>& shape, std::int64_t flat);

}  // namespace bcassim
