// Where the tests find ../shared/data (the real livers, the mestdagh benchmark): one lookup for
// every test, and the skip that names what is missing when a machine does not have it.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace bcassim::test {

// $BCASSIM_DATA (relative to the source tree when relative, as `make test` passes it), else
// <source>/../shared/data. Empty when that directory does not exist.
inline std::string sharedDataDir() {
  std::filesystem::path dir = std::filesystem::path(BCASSIM_SOURCE_DIR) / ".." / "shared" / "data";
  if (const char* env = std::getenv("BCASSIM_DATA"); env && *env) {
    dir = env;
    if (dir.is_relative()) dir = std::filesystem::path(BCASSIM_SOURCE_DIR) / dir;
  }
  return std::filesystem::is_directory(dir) ? dir.string() : std::string();
}

// The file or directory at `relative` under the shared data directory; empty when absent.
inline std::string sharedPath(const std::string& relative) {
  const std::string dir = sharedDataDir();
  if (dir.empty()) return {};
  const std::filesystem::path p = std::filesystem::path(dir) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

// A regular file at `relative` under the shared data directory; empty when absent.
inline std::string sharedFile(const std::string& relative) {
  const std::string p = sharedPath(relative);
  return !p.empty() && std::filesystem::is_regular_file(p) ? p : std::string();
}

}  // namespace bcassim::test

// `var`: the shared data file at `relative` (sharedFile), or the test is skipped, saying which.
#define SHARED_FILE_OR_SKIP(var, relative)                       \
  const std::string var = ::bcassim::test::sharedFile(relative); \
  if (var.empty())                                               \
  GTEST_SKIP() << "shared data file " << relative << " not found (set BCASSIM_DATA)"

// `var`: the shared data file or directory at `relative` (sharedPath), or the test is skipped.
#define SHARED_PATH_OR_SKIP(var, relative)                       \
  const std::string var = ::bcassim::test::sharedPath(relative); \
  if (var.empty()) GTEST_SKIP() << "shared data " << relative << " not found (set BCASSIM_DATA)"
