// A small typed binary file for checkpoints: a sequence of texts, numbers and matrices ending in
// a CRC-32 of them, written to a temporary file and renamed over the target so that a crash never
// leaves half a file.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

namespace bcassim {

class ArchiveWriter {
 public:
  // Writes to path + ".tmp" until commit(). Throws InputError "PATH.tmp: cannot create file
  // (REASON)" if it cannot be created.
  explicit ArchiveWriter(std::string path);
  // Removes the temporary file unless commit() succeeded.
  ~ArchiveWriter();
  ArchiveWriter(const ArchiveWriter&) = delete;
  ArchiveWriter& operator=(const ArchiveWriter&) = delete;
  void text(const std::string& s);
  void number(double x);
  void matrix(const Eigen::MatrixXd& m);
  // Writes the checksum, flushes and renames the file into place. When a write, the flush or the
  // rename fails, removes the temporary file and throws InputError "PATH: cannot write (REASON,
  // e.g. No space left on device); the previous file is kept".
  void commit();

 private:
  void write(const void* bytes, size_t size);
  [[noreturn]] void fail(int error);
  std::string path_;
  std::FILE* out_ = nullptr;
  std::uint32_t crc_ = 0;
  int error_ = 0;  // errno of the first failed write; later writes are skipped
  bool committed_ = false;
};

class ArchiveReader {
 public:
  // Throws InputError "PATH: cannot open (...)" when missing.
  ArchiveReader(std::string path, const std::string& whatFor);
  // Each throws InputError "PATH: damaged (expected ...)" when the next item is of another type
  // or the file ends.
  std::string text();
  double number();
  Eigen::MatrixXd matrix();
  const std::string& path() const { return path_; }

  // The checksum at the file's end: whether there is one (a 'C' tag and a CRC-32 in the last 5
  // bytes), the CRC-32 of the bytes before it and the one written. Once verified, the items read
  // stop before it.
  struct Checksum {
    bool present = false;
    std::uint32_t computed = 0, written = 0;
  };
  Checksum checksum();
  // The first item as a text when it is a text of at most maxBytes bytes (else empty); the next
  // read starts at the beginning again.
  std::string peekText(size_t maxBytes);

 private:
  void expect(char tag, const char* what);
  std::uint64_t bytesLeft();
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

// A checkpoint's header: "bcassim KIND checkpoint 2", then the key of the run it belongs to.
// (Format 1 had no checksum.)
void writeCheckpointHeader(ArchiveWriter& out, const std::string& kind, const std::string& key);
// Opens path as a KIND checkpoint of the run `key`, its checksum verified, positioned after the
// header. Throws InputError "PATH: no checkpoint to resume from (...)", "PATH: damaged (checksum
// ...); expected ...", "PATH: damaged (no checksum at its end ...)", "PATH: written by an older
// bcassim ...", "PATH: not a bcassim KIND checkpoint" or "PATH: written for another scene (...)".
ArchiveReader openCheckpoint(const std::string& path, const std::string& kind,
                             const std::string& key);

}  // namespace bcassim
