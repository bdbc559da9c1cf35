// Internal to the io module: the numeric value types of VTK files (legacy and XML), their sizes,
// and reading one value from binary bytes or from an ASCII token, as the VTK readers share them.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace bcassim::io {

enum class VtkScalar {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kInt64,
  kUInt64,
  kFloat32,
  kFloat64
};

int vtkScalarBytes(VtkScalar type);
bool vtkScalarIsInteger(VtkScalar type);

// The value at `bytes` (vtkScalarBytes(type) of them) in the given byte order, widened to double
// (exact for every float and for integers up to 2^53).
double decodeVtkScalar(const unsigned char* bytes, VtkScalar type, bool bigEndian);

// Parses an ASCII token as a value of `type`: integers must be whole and within the type's range,
// floats are rounded to the type as VTK's stream reads do (a Float32 token gives the nearest
// float). Returns an empty string on success, else why the token is not a value of the type, e.g.
// "expected an integer" or "out of range for a 32-bit float". A float may come out NaN or
// infinite: callers decide whether that is allowed.
std::string parseVtkScalar(std::string_view token, VtkScalar type, double& value);

}  // namespace bcassim::io
