// A small typed binary file for checkpoints: a sequence of texts, numbers and matrices, written
// to a temporary file and renamed over the target so that a crash never leaves half a file.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <fstream>
#include <string>

namespace bcassim {

class ArchiveWriter {
 public:
  // Writes to path + ".tmp" until commit(). Throws InputError if it cannot be created.
  explicit ArchiveWriter(std::string path);
  void text(const std::string& s);
  void number(double x);
  void matrix(const Eigen::MatrixXd& m);
  // Flushes and renames the file into place. Throws InputError if anything failed to write.
  void commit();

 private:
  std::string path_;
  std::ofstream out_;
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

 private:
  void expect(char tag, const char* what);
  std::uint64_t bytesLeft();
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

// A checkpoint's header: "bcassim KIND checkpoint 1", then the key of the run it belongs to.
void writeCheckpointHeader(ArchiveWriter& out, const std::string& kind, const std::string& key);
// Opens path as a KIND checkpoint of the run `key`, positioned after the header. Throws InputError
// "PATH: no checkpoint to resume from (...)", "PATH: not a bcassim KIND checkpoint" or
// "PATH: written for another scene (...)".
ArchiveReader openCheckpoint(const std::string& path, const std::string& kind,
                             const std::string& key);

}  // namespace bcassim
