#include "bcassim/io/VtkScalarValues.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace bcassim::io {
namespace {

// The range of an integer type.
void integerRange(VtkScalar type, long long& lo, unsigned long long& hi) {
  switch (type) {
    case VtkScalar::kInt8:
      lo = -128, hi = 127;
      return;
    case VtkScalar::kUInt8:
      lo = 0, hi = 255;
      return;
    case VtkScalar::kInt16:
      lo = -32768, hi = 32767;
      return;
    case VtkScalar::kUInt16:
      lo = 0, hi = 65535;
      return;
    case VtkScalar::kInt32:
      lo = std::numeric_limits<int32_t>::min(), hi = 2147483647u;
      return;
    case VtkScalar::kUInt32:
      lo = 0, hi = 4294967295u;
      return;
    case VtkScalar::kInt64:
      lo = std::numeric_limits<long long>::min(), hi = std::numeric_limits<long long>::max();
      return;
    default:
      lo = 0, hi = std::numeric_limits<unsigned long long>::max();
      return;
  }
}

std::string_view withoutPlus(std::string_view token) {
  // from_chars rejects a leading '+', which some writers emit and C++ streams accept.
  if (token.size() > 1 && token.front() == '+' && token[1] != '-' && token[1] != '+')
    token.remove_prefix(1);
  return token;
}

// A token from_chars found out of range, through strtod, which gives +-HUGE_VAL on overflow and the
// nearest subnormal or 0 on underflow (from_chars leaves the value unset in both cases).
double outOfRangeValue(std::string_view token) {
  return std::strtod(std::string(token).c_str(), nullptr);
}

}  // namespace

int vtkScalarBytes(VtkScalar type) {
  switch (type) {
    case VtkScalar::kInt8:
    case VtkScalar::kUInt8:
      return 1;
    case VtkScalar::kInt16:
    case VtkScalar::kUInt16:
      return 2;
    case VtkScalar::kInt32:
    case VtkScalar::kUInt32:
    case VtkScalar::kFloat32:
      return 4;
    default:
      return 8;
  }
}

bool vtkScalarIsInteger(VtkScalar type) {
  return type != VtkScalar::kFloat32 && type != VtkScalar::kFloat64;
}

double decodeVtkScalar(const unsigned char* bytes, VtkScalar type, bool bigEndian) {
  const int n = vtkScalarBytes(type);
  unsigned char b[8];
  for (int i = 0; i < n; ++i) b[i] = bigEndian ? bytes[n - 1 - i] : bytes[i];  // little-endian
  uint64_t u = 0;
  for (int i = n - 1; i >= 0; --i) u = (u << 8) | b[i];
  switch (type) {
    case VtkScalar::kInt8:
      return static_cast<int8_t>(u);
    case VtkScalar::kUInt8:
      return static_cast<uint8_t>(u);
    case VtkScalar::kInt16:
      return static_cast<int16_t>(u);
    case VtkScalar::kUInt16:
      return static_cast<uint16_t>(u);
    case VtkScalar::kInt32:
      return static_cast<int32_t>(u);
    case VtkScalar::kUInt32:
      return static_cast<uint32_t>(u);
    case VtkScalar::kInt64:
      return static_cast<double>(static_cast<int64_t>(u));
    case VtkScalar::kUInt64:
      return static_cast<double>(u);
    case VtkScalar::kFloat32: {
      const uint32_t bits = static_cast<uint32_t>(u);
      float f;
      std::memcpy(&f, &bits, 4);
      return f;
    }
    case VtkScalar::kFloat64: {
      double d;
      std::memcpy(&d, &u, 8);
      return d;
    }
  }
  return 0;
}

std::string parseVtkScalar(std::string_view token, VtkScalar type, double& value) {
  token = withoutPlus(token);
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (vtkScalarIsInteger(type)) {
    long long lo = 0;
    unsigned long long hi = 0;
    integerRange(type, lo, hi);
    if (!token.empty() && token.front() != '-') {
      unsigned long long u = 0;
      const auto [end, ec] = std::from_chars(first, last, u);
      if (ec == std::errc::result_out_of_range && end == last) return "out of range";
      if (ec != std::errc() || end != last) return "expected an integer";
      if (u > hi) return "out of range";
      value = static_cast<double>(u);
      return {};
    }
    long long v = 0;
    const auto [end, ec] = std::from_chars(first, last, v);
    if (ec == std::errc::result_out_of_range && end == last) return "out of range";
    if (ec != std::errc() || end != last) return "expected an integer";
    if (v < lo) return "out of range";
    value = static_cast<double>(v);
    return {};
  }
  if (type == VtkScalar::kFloat32) {
    float f = 0;
    const auto [end, ec] = std::from_chars(first, last, f);
    if (end != last || (ec != std::errc() && ec != std::errc::result_out_of_range))
      return "expected a number";
    if (ec == std::errc::result_out_of_range) {
      // Underflow gives the nearest float (0 or a subnormal), overflow is out of range, as
      // strtof does for VTK's stream reads.
      const double d = outOfRangeValue(token);
      if (std::abs(d) > std::numeric_limits<float>::max()) return "out of range";
      f = static_cast<float>(d);
    }
    value = f;
    return {};
  }
  double d = 0;
  const auto [end, ec] = std::from_chars(first, last, d);
  if (end != last || (ec != std::errc() && ec != std::errc::result_out_of_range))
    return "expected a number";
  if (ec == std::errc::result_out_of_range) {
    d = outOfRangeValue(token);
    if (std::isinf(d)) return "out of range";
  }
  value = d;
  return {};
}

}  // namespace bcassim::io
