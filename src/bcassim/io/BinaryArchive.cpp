#include "bcassim/io/BinaryArchive.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

constexpr char kText = 'T', kNumber = 'N', kMatrix = 'M';

template <class T>
void put(std::ofstream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

ArchiveWriter::ArchiveWriter(std::string path) : path_(std::move(path)) {
  out_.open(path_ + ".tmp", std::ios::binary | std::ios::trunc);
  if (!out_) throw InputError(fmt::format("{}.tmp: cannot write file", path_));
}

void ArchiveWriter::text(const std::string& s) {
  out_.put(kText);
  put<std::uint64_t>(out_, s.size());
  out_.write(s.data(), static_cast<std::streamsize>(s.size()));
}

void ArchiveWriter::number(double x) {
  out_.put(kNumber);
  put(out_, x);
}

void ArchiveWriter::matrix(const Eigen::MatrixXd& m) {
  out_.put(kMatrix);
  put<std::int64_t>(out_, m.rows());
  put<std::int64_t>(out_, m.cols());
  out_.write(reinterpret_cast<const char*>(m.data()),
             static_cast<std::streamsize>(sizeof(double) * m.size()));
}

void ArchiveWriter::commit() {
  out_.flush();
  if (!out_) throw InputError(fmt::format("{}.tmp: cannot write file", path_));
  out_.close();
  std::error_code ec;
  std::filesystem::rename(path_ + ".tmp", path_, ec);
  if (ec) throw InputError(fmt::format("{}: cannot write file ({})", path_, ec.message()));
}

ArchiveReader::ArchiveReader(std::string path, const std::string& whatFor)
    : path_(std::move(path)), in_(path_, std::ios::binary) {
  if (!in_) throw InputError(fmt::format("{}: cannot open ({})", path_, whatFor));
  in_.seekg(0, std::ios::end);
  size_ = static_cast<std::uint64_t>(std::max<std::streamoff>(in_.tellg(), 0));
  in_.seekg(0);
}

std::uint64_t ArchiveReader::bytesLeft() {
  const std::streamoff at = in_.tellg();
  return at < 0 || static_cast<std::uint64_t>(at) > size_ ? 0 : size_ - at;
}

void ArchiveReader::expect(char tag, const char* what) {
  char got = 0;
  if (!in_.get(got) || got != tag)
    throw InputError(fmt::format("{}: damaged (expected {})", path_, what));
}

std::string ArchiveReader::text() {
  expect(kText, "a text");
  std::uint64_t n = 0;
  in_.read(reinterpret_cast<char*>(&n), sizeof n);
  // A length beyond the bytes left is damage, refused before anything is allocated for it.
  if (!in_ || n > (1u << 26) || n > bytesLeft())
    throw InputError(fmt::format("{}: damaged (expected a text)", path_));
  std::string s(n, '\0');
  in_.read(s.data(), static_cast<std::streamsize>(n));
  if (!in_) throw InputError(fmt::format("{}: damaged (expected a text)", path_));
  return s;
}

double ArchiveReader::number() {
  expect(kNumber, "a number");
  double x = 0;
  in_.read(reinterpret_cast<char*>(&x), sizeof x);
  if (!in_) throw InputError(fmt::format("{}: damaged (expected a number)", path_));
  return x;
}

Eigen::MatrixXd ArchiveReader::matrix() {
  expect(kMatrix, "a matrix");
  std::int64_t rows = -1, cols = -1;
  in_.read(reinterpret_cast<char*>(&rows), sizeof rows);
  in_.read(reinterpret_cast<char*>(&cols), sizeof cols);
  if (!in_ || rows < 0 || cols < 0 ||
      (cols > 0 && static_cast<std::uint64_t>(rows) > bytesLeft() / sizeof(double) / cols))
    throw InputError(fmt::format("{}: damaged (expected a matrix)", path_));
  Eigen::MatrixXd m(rows, cols);
  in_.read(reinterpret_cast<char*>(m.data()),
           static_cast<std::streamsize>(sizeof(double) * m.size()));
  if (!in_ || !m.allFinite())
    throw InputError(fmt::format("{}: damaged (expected a {} x {} matrix of finite numbers)", path_,
                                 rows, cols));
  return m;
}

namespace {
std::string checkpointMagic(const std::string& kind) {
  return fmt::format("bcassim {} checkpoint 1", kind);
}
}  // namespace

void writeCheckpointHeader(ArchiveWriter& out, const std::string& kind, const std::string& key) {
  out.text(checkpointMagic(kind));
  out.text(key);
}

ArchiveReader openCheckpoint(const std::string& path, const std::string& kind,
                             const std::string& key) {
  if (!std::filesystem::exists(path))
    throw InputError(fmt::format("{}: no checkpoint to resume from (run without --resume)", path));
  ArchiveReader in(path, "the checkpoint to resume from");
  if (in.text() != checkpointMagic(kind))
    throw InputError(fmt::format("{}: not a bcassim {} checkpoint", path, kind));
  const std::string written = in.text();
  if (written != key)
    throw InputError(fmt::format("{}: written for another scene ({}); this scene is {}", path,
                                 io::excerpt(written, 1000), key));
  return in;
}

}  // namespace bcassim
