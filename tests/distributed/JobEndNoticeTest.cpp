// The SIGTERM handlers of an MPI run, in forked children: rank 0 writes the line last set and
// exits at once; a worker outlives its SIGTERM by the grace, so rank 0 exits first (mpirun's
// SIGKILL follows the first exit).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <string>
#include <thread>

#include "bcassim/distributed/JobEndNotice.h"

namespace bcassim {
namespace {

using Clock = std::chrono::steady_clock;

struct Child {
  pid_t pid = -1;
  int stderrPipe = -1;  // the read end
};

// A child whose stderr comes back through a pipe: it runs `setUp`, tells the parent through
// `ready` that it did, and waits for signals.
template <class SetUp>
Child forkWaiting(SetUp setUp) {
  int err[2], ready[2];
  EXPECT_EQ(::pipe(err), 0);
  EXPECT_EQ(::pipe(ready), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(err[1], STDERR_FILENO);
    ::close(err[0]);
    ::close(ready[0]);
    setUp();
    const char one = 1;
    if (::write(ready[1], &one, 1) != 1) ::_exit(100);
    for (;;) ::pause();
  }
  ::close(err[1]);
  ::close(ready[1]);
  char one = 0;
  EXPECT_EQ(::read(ready[0], &one, 1), 1);
  ::close(ready[0]);
  return {pid, err[0]};
}

std::string readAll(int fd) {
  std::string text;
  char buffer[256];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, n);
  ::close(fd);
  return text;
}

// SIGTERM to the child; its exit code once it has ended (-1 if it did not exit by itself).
int exitCodeAfterSigterm(const Child& child) {
  if (child.pid <= 0 || ::kill(child.pid, SIGTERM) != 0) return -1;
  int status = 0;
  if (::waitpid(child.pid, &status, 0) != child.pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

TEST(JobEndNotice, SigtermWritesTheLastLineSetAndExitsWithTheCode) {
  const Child child = forkWaiting([] {
    installJobEndNotice(3);
    setJobEndNotice("bcassim: error: first");
    setJobEndNotice("bcassim: error: assimilation step 4: the MPI job was ended");
  });
  EXPECT_EQ(exitCodeAfterSigterm(child), 3);
  EXPECT_EQ(readAll(child.stderrPipe),
            "bcassim: error: assimilation step 4: the MPI job was ended\n");
}

TEST(JobEndNotice, BeforeALineIsSetSigtermExitsSilently) {
  const Child child = forkWaiting([] { installJobEndNotice(3); });
  EXPECT_EQ(exitCodeAfterSigterm(child), 3);
  EXPECT_EQ(readAll(child.stderrPipe), "");
}

// Still alive well after its SIGTERM (a second signal during the grace does not shorten it), gone
// with the code once the second has passed.
TEST(JobEndNotice, AWorkerOutlivesItsSigtermByASecond) {
  const Child child = forkWaiting([] { installWorkerTerminationGrace(3); });
  ASSERT_GT(child.pid, 0);
  const auto sent = Clock::now();
  ASSERT_EQ(::kill(child.pid, SIGTERM), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(child.pid, SIGTERM);
  int status = 0;
  EXPECT_EQ(::waitpid(child.pid, &status, WNOHANG), 0) << "ended within 0.3 s of its SIGTERM";
  ASSERT_EQ(::waitpid(child.pid, &status, 0), child.pid);
  const double seconds = std::chrono::duration<double>(Clock::now() - sent).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);
  EXPECT_GE(seconds, 0.99);
  EXPECT_EQ(readAll(child.stderrPipe), "");
}

}  // namespace
}  // namespace bcassim
