// Progress bar of `bcassim assimilate` and `validate` on stderr: percentage, step, elapsed time,
// ETA, ms per step and the current estimate; only for runs longer than about a second.
#pragma once
#include <cstdio>

#include "bcassim/cli/ProgressLine.h"
#include "bcassim/run/AssimilationRunner.h"

namespace bcassim {

class AssimilationProgressBar {
 public:
  // out: where to draw (stderr). On a terminal the bar is redrawn in place at most 10 times a
  // second; otherwise one line is printed every 10 %.
  explicit AssimilationProgressBar(std::FILE* out) : line_(out, 20) {}

  void update(const AssimilationProgress& p);
  // Ends the bar's line if one was drawn.
  void finish() { line_.finish(); }

 private:
  ProgressLine line_;
};

}  // namespace bcassim
