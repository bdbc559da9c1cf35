// The lock on a run's output directory: a second run into the same --out is refused with one line
// while the first holds it, and the directory is free again once the holder has gone.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include "bcassim/Error.h"
#include "bcassim/io/OutputDirectoryLock.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::runBcassim;
using test::writeText;

const char* kLockScene =
    "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [4, 1, 1]}\n"
    "time: {steps: 2}\nfixed:\n  - region: {nodes: [0, 5]}\n"
    "markers:\n  - points: [[0.1, 0.02, 0.02]]\n";

const std::string kRefusal =
    ": another bcassim run is writing into this directory (it holds .bcassim.lock); wait for it "
    "to end or choose another --out";

TEST(OutputDirectoryLock, SecondLockOnTheSameDirectoryIsRefusedUntilTheFirstIsReleased) {
  const std::string dir = (freshDir() / "out").string();
  {
    const io::OutputDirectoryLock first(dir);  // creates the directory
    try {
      io::OutputDirectoryLock second(dir);
      FAIL() << "a second lock was granted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), dir + kRefusal);
    }
  }
  EXPECT_NO_THROW(io::OutputDirectoryLock again(dir));
}

// The holder here is another open file description in this process, as a second process's would
// be: flock conflicts between descriptions, not only between processes.
TEST(OutputDirectoryLock, SimulateIntoALockedDirectoryIsRefusedWithExitCode2) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml", kLockScene);
  std::filesystem::create_directories(dir / "out");
  const int held = ::open((dir / "out" / ".bcassim.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);
  const test::CliResult refused = runBcassim(dir, "simulate scene.yaml --out out --quiet");
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_EQ(refused.err, "bcassim: error: out" + kRefusal + "\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "markers.csv"));
  ::close(held);  // as a finished or crashed run's lock: gone with its descriptor
  const test::CliResult after = runBcassim(dir, "simulate scene.yaml --out out --quiet");
  EXPECT_EQ(after.exitCode, 0) << after.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "markers.csv"));
}

TEST(OutputDirectoryLock, AssimilateIntoALockedDirectoryIsRefused) {
  const auto dir = freshDir();
  writeText(dir / "scene.yaml", kLockScene);
  const io::OutputDirectoryLock held((dir / "out").string());
  const test::CliResult refused = runBcassim(dir, "assimilate scene.yaml --out out --quiet");
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_EQ(refused.err, "bcassim: error: out" + kRefusal + "\n");
}

}  // namespace
}  // namespace bcassim
