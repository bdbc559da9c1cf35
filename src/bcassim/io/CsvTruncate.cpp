#include "bcassim/io/CsvTruncate.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"

namespace bcassim {

void keepCsvRowsUpTo(const std::string& path, double limit) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open (a file of the run to resume)", path));
  std::ostringstream kept;
  for (std::string line; std::getline(in, line);) {
    const bool complete = !in.eof();  // the last line of a killed run may lack its newline
    const char* begin = line.c_str();
    char* end = nullptr;
    const double first = std::strtod(begin, &end);
    const bool numeric = end != begin && (*end == ',' || *end == '\0');
    // Headers and comments stay; a row stays when it is whole and not after the limit.
    if (!numeric || (complete && first <= limit)) kept << line << '\n';
  }
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    const std::string text = kept.str();
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      const int error = errno;
      std::remove(temporary.c_str());  // the file of the run stays as it was
      errno = error;
      io::throwWriteError(temporary);
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw InputError(fmt::format("{}: cannot replace ({})", path, ec.message()));
  }
}

std::ofstream openStepCsv(const std::string& path, const std::string& header,
                          std::optional<double> resumeUpTo) {
  std::ofstream out;
  if (resumeUpTo) {
    keepCsvRowsUpTo(path, *resumeUpTo);
    out.open(path, std::ios::app);
  } else {
    io::createParentDirectory(path);
    out.open(path, std::ios::trunc);
    out << header << '\n';
  }
  if (!out) io::throwWriteError(path);
  return out;
}

}  // namespace bcassim
