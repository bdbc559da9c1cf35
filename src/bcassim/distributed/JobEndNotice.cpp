#include "bcassim/distributed/JobEndNotice.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>

namespace bcassim {
namespace {

// Two buffers: the handler reads the one published while the next is written into the other
// (only async-signal-safe calls in the handler: no allocation, no stdio).
constexpr size_t kCapacity = 1024;
char buffers[2][kCapacity];
size_t lengths[2] = {0, 0};
std::atomic<int> published{-1};
int endCode = 1;

void onTerminate(int) {
  const int i = published.load();
  if (i >= 0) {
    ssize_t ignored = ::write(STDERR_FILENO, buffers[i], lengths[i]);
    (void)ignored;
  }
  ::_exit(endCode);
}

void onWorkerTerminate(int) {
  timespec left{1, 0};
  while (::nanosleep(&left, &left) == -1 && errno == EINTR) {
  }
  ::_exit(endCode);
}

void installHandler(int exitCode, void (*handler)(int)) {
  endCode = exitCode;
  struct sigaction action {};
  action.sa_handler = handler;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

void installJobEndNotice(int exitCode) { installHandler(exitCode, onTerminate); }

void installWorkerTerminationGrace(int exitCode) { installHandler(exitCode, onWorkerTerminate); }

void setJobEndNotice(const std::string& line) {
  const int next = published.load() == 0 ? 1 : 0;
  const size_t n = std::min(line.size(), kCapacity - 1);
  std::memcpy(buffers[next], line.data(), n);
  buffers[next][n] = '\n';
  lengths[next] = n + 1;
  published.store(next);
}

}  // namespace bcassim
