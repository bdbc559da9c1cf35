// A 3-vector as short text for messages, reports and scene files: "[x, y, z]".
#pragma once
#include <fmt/format.h>

#include <string>

#include "bcassim/Types.h"

namespace bcassim {

// "[x, y, z]" with `digits` significant digits (17 reads back the same double).
inline std::string formatVec3(const Vec3& v, int digits = 6) {
  return fmt::format("[{:.{}g}, {:.{}g}, {:.{}g}]", v(0), digits, v(1), digits, v(2), digits);
}

}  // namespace bcassim
