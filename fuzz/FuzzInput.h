// What every fuzz target shares: the input written to a file of this process (the readers take
// paths, and reading the real file exercises the real code), and the one outcome allowed for bad
// input, an InputError; any other exception, crash, leak or hang is a finding.
#pragma once
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "bcassim/Error.h"

namespace bcassim::fuzz {

// A directory of this process, in memory (/dev/shm) when the system has one.
inline const std::filesystem::path& fuzzDirectory() {
  static const std::filesystem::path dir = [] {
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    std::filesystem::path d = base / ("bcassim-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

// Writes the input to "<fuzz directory>/<name>" and returns the path.
inline std::string writeInput(const uint8_t* data, size_t size, const std::string& name) {
  const std::string path = (fuzzDirectory() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs `read`, accepting only success or an InputError of one line.
template <class Read>
void expectOnlyInputErrors(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.find('\n') != std::string::npos || message.find('\r') != std::string::npos)
      __builtin_trap();  // an error message must be one line
  }
}

}  // namespace bcassim::fuzz
