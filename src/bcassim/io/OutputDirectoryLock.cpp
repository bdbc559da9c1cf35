#include "bcassim/io/OutputDirectoryLock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "bcassim/Error.h"

namespace bcassim::io {

OutputDirectoryLock::OutputDirectoryLock(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw InputError(fmt::format("{}: cannot create the output directory ({})", dir, ec.message()));
  const std::string path = (std::filesystem::path(dir) / kFileName).string();
  // O_CLOEXEC: a plotting script started by the run must not inherit (and outlive with) the lock.
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw InputError(
        fmt::format("{}: cannot create the lock file ({})", path, std::strerror(errno)));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      throw InputError(fmt::format(
          "{}: another bcassim run is writing into this directory (it holds {}); wait for it to "
          "end or choose another --out",
          dir, kFileName));
    throw InputError(fmt::format("{}: cannot lock ({})", path, std::strerror(error)));
  }
}

OutputDirectoryLock::~OutputDirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the descriptor releases the flock
}

}  // namespace bcassim::io
