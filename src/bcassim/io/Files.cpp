#include "bcassim/io/Files.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "bcassim/Error.h"

namespace bcassim::io {

void requireReadableFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(fmt::format("{}: cannot open file", path));
}

MappedFile::MappedFile(const std::string& path) {
  requireReadableFile(path);
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw InputError(fmt::format("{}: cannot open file", path));
  struct stat info;
  if (::fstat(fd, &info) != 0) {
    ::close(fd);
    throw InputError(fmt::format("{}: cannot open file", path));
  }
  size_ = static_cast<size_t>(info.st_size);
  if (size_ > 0) {
    void* map = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (map == MAP_FAILED) {
      ::close(fd);
      throw InputError(fmt::format("{}: cannot read file", path));
    }
    data_ = static_cast<const char*>(map);
    mapped_ = true;
  }
  ::close(fd);
}

MappedFile::~MappedFile() {
  if (mapped_) ::munmap(const_cast<char*>(data_), size_);
}

void createParentDirectory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  if (ec)
    throw OutputError(
        fmt::format("{}: cannot create directory '{}' ({})", path, parent.string(), ec.message()));
}

std::string systemErrorText(int error) {
  return error == 0 ? std::string("unknown cause") : std::string(std::strerror(error));
}

void throwWriteError(const std::string& path) {
  throw OutputError(fmt::format("{}: cannot write file ({})", path, systemErrorText(errno)));
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace bcassim::io
