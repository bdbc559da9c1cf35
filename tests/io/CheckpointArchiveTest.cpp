// Checkpoint archives as outputs to trust: a CRC-32 at the end refuses a damaged or cut-short
// file by name, format 1 (no checksum) is refused, and a failed write says why and leaves no
// temporary file.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/io/BinaryArchive.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::readText;
using test::TempDir;
using test::writeText;

// A simulation checkpoint of the run "beam" holding a number and a 2 x 2 matrix.
std::string writeCheckpoint(const std::string& path) {
  ArchiveWriter out(path);
  writeCheckpointHeader(out, "simulation", "beam");
  out.number(0.25);
  out.matrix(Eigen::MatrixXd::Identity(2, 2));
  out.commit();
  return path;
}

std::uint32_t crc32Of(const std::string& bytes) {
  return static_cast<std::uint32_t>(
      ::crc32(0, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(CheckpointArchive, EndsWithTheCrc32OfItsContentsAndReadsBack) {
  TempDir dir;
  const std::string path = writeCheckpoint(dir.file("checkpoint.bin"));
  const std::string bytes = readText(path);
  // header texts (1 + 8 + 31, 1 + 8 + 4), number (1 + 8), matrix (1 + 16 + 32), checksum (1 + 4)
  ASSERT_EQ(bytes.size(), 40u + 13u + 9u + 49u + 5u);
  const std::string contents = bytes.substr(0, bytes.size() - 5);
  EXPECT_EQ(bytes[bytes.size() - 5], 'C');
  std::uint32_t written = 0;
  std::memcpy(&written, bytes.data() + bytes.size() - 4, 4);
  EXPECT_EQ(written, crc32Of(contents));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  ArchiveReader in = openCheckpoint(path, "simulation", "beam");
  EXPECT_EQ(in.number(), 0.25);
  EXPECT_EQ(in.matrix(), Eigen::MatrixXd::Identity(2, 2));
  // The checksum is not an item: reading on is damage, not the checksum's bytes as a number.
  EXPECT_EQ(message([&] { in.number(); }), path + ": damaged (expected a number)");
}

TEST(CheckpointArchive, OneFlippedByteIsRefusedByItsChecksum) {
  TempDir dir;
  const std::string path = writeCheckpoint(dir.file("checkpoint.bin"));
  std::string bytes = readText(path);
  const std::uint32_t written = crc32Of(bytes.substr(0, bytes.size() - 5));
  bytes[90] ^= 0x10;  // inside the matrix's values
  writeText(path, bytes);
  const std::uint32_t damaged = crc32Of(bytes.substr(0, bytes.size() - 5));
  ASSERT_NE(damaged, written);
  EXPECT_EQ(message([&] { openCheckpoint(path, "simulation", "beam"); }),
            fmt::format("{}: damaged (checksum {:08x}); expected {:08x}, the CRC-32 written at "
                        "its end",
                        path, damaged, written));
}

TEST(CheckpointArchive, CutShortIsRefusedAsHavingNoChecksum) {
  TempDir dir;
  const std::string path = writeCheckpoint(dir.file("checkpoint.bin"));
  const std::string bytes = readText(path);
  writeText(path, bytes.substr(0, bytes.size() - 20));
  EXPECT_EQ(message([&] { openCheckpoint(path, "simulation", "beam"); }),
            path +
                ": damaged (no checksum at its end: cut short?); expected a 'C' tag and a CRC-32 "
                "in its last 5 bytes");
}

TEST(CheckpointArchive, FormatOneWithoutChecksumIsRefused) {
  TempDir dir;
  const std::string magic = "bcassim simulation checkpoint 1";
  std::string bytes = "T";
  const std::uint64_t n = magic.size();
  bytes.append(reinterpret_cast<const char*>(&n), 8);
  bytes += magic;
  const std::string path = writeText(dir.file("checkpoint.bin"), bytes);
  EXPECT_EQ(message([&] { openCheckpoint(path, "simulation", "beam"); }),
            path +
                ": written by an older bcassim (checkpoint format 1, without a checksum); run "
                "without --resume");
}

TEST(CheckpointArchive, AnotherKindIsNotThisKindOfCheckpoint) {
  TempDir dir;
  const std::string path = writeCheckpoint(dir.file("checkpoint.bin"));
  EXPECT_EQ(message([&] { openCheckpoint(path, "assimilation", "beam"); }),
            path + ": not a bcassim assimilation checkpoint");
}

// A full disk, as /dev/full gives one: the reason is named, the temporary file is gone and the
// previous checkpoint stays as it was.
TEST(CheckpointArchive, FullDiskSaysWhyAndLeavesNoTemporaryFile) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  TempDir dir;
  const std::string path = writeCheckpoint(dir.file("checkpoint.bin"));
  const std::string previous = readText(path);
  std::filesystem::create_symlink("/dev/full", path + ".tmp");
  EXPECT_EQ(message([&] { writeCheckpoint(path); }),
            path + ": cannot write (No space left on device); the previous file is kept");
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(path + ".tmp")));
  EXPECT_EQ(readText(path), previous);
}

TEST(CheckpointArchive, ReadOnlyDirectorySaysWhy) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores directory permissions";
  TempDir dir;
  const std::string folder = dir.file("locked");
  std::filesystem::create_directories(folder);
  std::filesystem::permissions(
      folder, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  const std::string path = folder + "/checkpoint.bin";
  EXPECT_EQ(message([&] { writeCheckpoint(path); }),
            path + ".tmp: cannot create file (Permission denied)");
  std::filesystem::permissions(folder, std::filesystem::perms::owner_all);
  EXPECT_TRUE(std::filesystem::is_empty(folder));
}

// An error while the items are written (the caller throws) removes the temporary file too.
TEST(CheckpointArchive, AbandonedWriterRemovesItsTemporaryFile) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  {
    ArchiveWriter out(path);
    out.number(1.0);
    EXPECT_TRUE(std::filesystem::exists(path + ".tmp"));
  }
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace bcassim
