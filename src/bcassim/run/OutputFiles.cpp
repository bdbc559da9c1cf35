#include "bcassim/run/OutputFiles.h"

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"

namespace bcassim {

std::ofstream openForWriting(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path);
  if (!out) io::throwWriteError(path.string());
  return out;
}

void flushOrThrow(std::ofstream& out, const std::filesystem::path& path) {
  out.flush();
  if (!out) io::throwWriteError(path.string());
}

void createOutputDirectory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw OutputError(dir.string() + ": cannot create directory (" + ec.message() + ")");
}

}  // namespace bcassim
