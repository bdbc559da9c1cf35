// Progress bar of the command-line program on stderr: percentage, step, elapsed time, ETA and
// ms per step, shown only for runs that last more than about a second.
#pragma once
#include <cstdio>

#include "bcassim/cli/ProgressLine.h"
#include "bcassim/run/SimulationRunner.h"

namespace bcassim {

class ProgressBar {
 public:
  // out: where to draw (stderr). On a terminal the bar is redrawn in place at most 10 times a
  // second; otherwise one line is printed every 10 %.
  explicit ProgressBar(std::FILE* out) : line_(out, 24) {}

  void update(const RunProgress& p);
  // Ends the bar's line if one was drawn.
  void finish() { line_.finish(); }

 private:
  ProgressLine line_;
};

}  // namespace bcassim
