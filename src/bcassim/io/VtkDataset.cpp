#include "bcassim/io/VtkDataset.h"

#include <fmt/format.h>

namespace bcassim::io {

std::string VtkDataset::cellLocation(long long c) const {
  if (c >= 0 && c < static_cast<long long>(cells.lines.size()))
    return fmt::format("{}:{}", source, cells.lines[c]);
  if (cellsLine > 0) return fmt::format("{}:{}", source, cellsLine);
  return source;
}

}  // namespace bcassim::io
