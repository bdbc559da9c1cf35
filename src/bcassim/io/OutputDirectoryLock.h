// An exclusive lock on a run's output directory (flock on DIR/.bcassim.lock), held while the run
// writes there so that two runs into the same --out cannot interleave their files.
#pragma once
#include <string>

namespace bcassim::io {

class OutputDirectoryLock {
 public:
  // Creates `dir` if missing and locks it. Throws InputError "DIR: another bcassim run is
  // writing into this directory (...)" when a running process holds the lock; the kernel drops
  // the lock of a process that ends, so a crashed run never blocks the next one.
  explicit OutputDirectoryLock(const std::string& dir);
  ~OutputDirectoryLock();
  OutputDirectoryLock(const OutputDirectoryLock&) = delete;
  OutputDirectoryLock& operator=(const OutputDirectoryLock&) = delete;

  // The lock file's name inside the directory.
  static constexpr const char* kFileName = ".bcassim.lock";

 private:
  int fd_ = -1;
};

}  // namespace bcassim::io
