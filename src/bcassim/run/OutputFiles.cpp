#include "bcassim/run/OutputFiles.h"

#include "bcassim/Error.h"

namespace bcassim {

std::ofstream openForWriting(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path);
  if (!out) throw InputError(path.string() + ": cannot write file");
  return out;
}

void flushOrThrow(std::ofstream& out, const std::filesystem::path& path) {
  out.flush();
  if (!out) throw InputError(path.string() + ": write failed");
}

void createOutputDirectory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create directory (" + ec.message() + ")");
}

}  // namespace bcassim
