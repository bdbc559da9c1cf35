#include "bcassim/io/BinaryArchive.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/TextLines.h"

namespace bcassim {
namespace {

constexpr char kText = 'T', kNumber = 'N', kMatrix = 'M', kChecksum = 'C';
constexpr size_t kChecksumBytes = 1 + sizeof(std::uint32_t);

std::uint32_t crc32Of(std::uint32_t crc, const void* bytes, size_t size) {
  const auto* p = static_cast<const Bytef*>(bytes);
  while (size > 0) {  // zlib's crc32 takes a 32-bit length
    const auto n = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, p, n));
    p += n;
    size -= n;
  }
  return crc;
}

}  // namespace

ArchiveWriter::ArchiveWriter(std::string path) : path_(std::move(path)) {
  out_ = std::fopen((path_ + ".tmp").c_str(), "wb");
  if (!out_)
    throw InputError(
        fmt::format("{}.tmp: cannot create file ({})", path_, io::systemErrorText(errno)));
}

ArchiveWriter::~ArchiveWriter() {
  if (committed_) return;
  if (out_) std::fclose(out_);
  std::remove((path_ + ".tmp").c_str());
}

void ArchiveWriter::write(const void* bytes, size_t size) {
  if (error_ != 0 || size == 0) return;
  crc_ = crc32Of(crc_, bytes, size);
  if (std::fwrite(bytes, 1, size, out_) != size) error_ = errno != 0 ? errno : EIO;
}

void ArchiveWriter::text(const std::string& s) {
  write(&kText, 1);
  const std::uint64_t n = s.size();
  write(&n, sizeof n);
  write(s.data(), s.size());
}

void ArchiveWriter::number(double x) {
  write(&kNumber, 1);
  write(&x, sizeof x);
}

void ArchiveWriter::matrix(const Eigen::MatrixXd& m) {
  write(&kMatrix, 1);
  const std::int64_t rows = m.rows(), cols = m.cols();
  write(&rows, sizeof rows);
  write(&cols, sizeof cols);
  write(m.data(), sizeof(double) * static_cast<size_t>(m.size()));
}

void ArchiveWriter::fail(int error) {
  std::fclose(out_);
  out_ = nullptr;
  std::remove((path_ + ".tmp").c_str());
  throw OutputError(fmt::format("{}: cannot write ({}); the previous file is kept", path_,
                                io::systemErrorText(error)));
}

void ArchiveWriter::commit() {
  const std::uint32_t crc = crc_;
  write(&kChecksum, 1);
  write(&crc, sizeof crc);
  if (error_ != 0) fail(error_);
  if (std::fflush(out_) != 0) fail(errno);
  const int closed = std::fclose(out_);
  out_ = nullptr;
  if (closed != 0) fail(errno);
  if (std::rename((path_ + ".tmp").c_str(), path_.c_str()) != 0) fail(errno);
  committed_ = true;
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
  if (bytesLeft() == 0 || !in_.get(got) || got != tag)
    throw InputError(fmt::format("{}: damaged (expected {})", path_, what));
}

std::string ArchiveReader::text() {
  expect(kText, "a text");
  std::uint64_t n = 0;
  if (bytesLeft() < sizeof n) throw InputError(fmt::format("{}: damaged (expected a text)", path_));
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
  if (bytesLeft() < sizeof x)
    throw InputError(fmt::format("{}: damaged (expected a number)", path_));
  in_.read(reinterpret_cast<char*>(&x), sizeof x);
  if (!in_) throw InputError(fmt::format("{}: damaged (expected a number)", path_));
  return x;
}

Eigen::MatrixXd ArchiveReader::matrix() {
  expect(kMatrix, "a matrix");
  std::int64_t rows = -1, cols = -1;
  if (bytesLeft() < sizeof rows + sizeof cols)
    throw InputError(fmt::format("{}: damaged (expected a matrix)", path_));
  in_.read(reinterpret_cast<char*>(&rows), sizeof rows);
  in_.read(reinterpret_cast<char*>(&cols), sizeof cols);
  // Each size within the bytes left as well: a 0 x 2^62 matrix holds nothing but would take
  // forever to check.
  const std::uint64_t left = bytesLeft();
  if (!in_ || rows < 0 || cols < 0 || static_cast<std::uint64_t>(rows) > left ||
      static_cast<std::uint64_t>(cols) > left ||
      (cols > 0 && static_cast<std::uint64_t>(rows) > left / sizeof(double) / cols))
    throw InputError(fmt::format("{}: damaged (expected a matrix)", path_));
  Eigen::MatrixXd m(rows, cols);
  in_.read(reinterpret_cast<char*>(m.data()),
           static_cast<std::streamsize>(sizeof(double) * m.size()));
  if (!in_ || !m.allFinite())
    throw InputError(fmt::format("{}: damaged (expected a {} x {} matrix of finite numbers)", path_,
                                 rows, cols));
  return m;
}

ArchiveReader::Checksum ArchiveReader::checksum() {
  Checksum c;
  if (size_ < kChecksumBytes) return c;
  const std::uint64_t contents = size_ - kChecksumBytes;
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(contents));
  char tag = 0;
  in_.get(tag);
  in_.read(reinterpret_cast<char*>(&c.written), sizeof c.written);
  if (!in_ || tag != kChecksum) {
    in_.clear();
    in_.seekg(0);
    return c;
  }
  c.present = true;
  in_.seekg(0);
  std::string buffer(std::min<std::uint64_t>(contents, 1u << 20), '\0');
  for (std::uint64_t left = contents; left > 0;) {
    const auto n = static_cast<std::streamsize>(std::min<std::uint64_t>(left, buffer.size()));
    if (!in_.read(buffer.data(), n)) throw InputError(fmt::format("{}: cannot read file", path_));
    c.computed = crc32Of(c.computed, buffer.data(), static_cast<size_t>(n));
    left -= static_cast<std::uint64_t>(n);
  }
  in_.seekg(0);
  size_ = contents;  // the items end where the checksum begins
  return c;
}

std::string ArchiveReader::peekText(size_t maxBytes) {
  std::string s;
  char tag = 0;
  std::uint64_t n = 0;
  in_.clear();
  in_.seekg(0);
  if (in_.get(tag) && tag == kText && in_.read(reinterpret_cast<char*>(&n), sizeof n) &&
      n <= maxBytes && n <= bytesLeft()) {
    s.resize(n);
    if (!in_.read(s.data(), static_cast<std::streamsize>(n))) s.clear();
  }
  in_.clear();
  in_.seekg(0);
  return s;
}

namespace {
std::string checkpointMagic(const std::string& kind, int format = 2) {
  return fmt::format("bcassim {} checkpoint {}", kind, format);
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
  const std::string magic = in.peekText(64);
  if (magic == checkpointMagic(kind, 1))
    throw InputError(fmt::format(
        "{}: written by an older bcassim (checkpoint format 1, without a checksum); run without "
        "--resume",
        path));
  const ArchiveReader::Checksum checksum = in.checksum();
  if (!checksum.present) {
    if (magic == checkpointMagic(kind))
      throw InputError(fmt::format(
          "{}: damaged (no checksum at its end: cut short?); expected a 'C' tag and a CRC-32 in "
          "its last 5 bytes",
          path));
    throw InputError(fmt::format("{}: not a bcassim {} checkpoint", path, kind));
  }
  if (checksum.computed != checksum.written)
    throw InputError(
        fmt::format("{}: damaged (checksum {:08x}); expected {:08x}, the CRC-32 "
                    "written at its end",
                    path, checksum.computed, checksum.written));
  if (in.text() != checkpointMagic(kind))
    throw InputError(fmt::format("{}: not a bcassim {} checkpoint", path, kind));
  const std::string written = in.text();
  if (written != key)
    throw InputError(fmt::format("{}: written for another scene ({}); this scene is {}", path,
                                 io::excerpt(written, 1000), key));
  return in;
}

}  // namespace bcassim
