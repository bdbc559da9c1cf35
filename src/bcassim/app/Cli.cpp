#include "bcassim/app/Cli.h"

#include <cstdio>

namespace bcassim {
int runCli(int, char**) {
  std::puts("bcassim: no command yet");
  return 0;
}
}  // namespace bcassim
