// The one-line progress display both CLI bars draw on stderr: a bar, percentage, step, elapsed
// time, ETA and ms per step, shown only for runs that last more than about a second.
#pragma once
#include <cstdio>
#include <string>

namespace bcassim {

class ProgressLine {
 public:
  // out: where to draw (stderr). On a terminal the line is redrawn in place at most 10 times a
  // second; otherwise one line is printed every 10 %. width: characters of the bar itself.
  ProgressLine(std::FILE* out, int width);
  ~ProgressLine();

  // Draws "[###...]  NN% step done/total<label>  elapsed E  ETA T  X ms/step<suffix>" when due.
  void update(long done, long total, double elapsedSeconds, double meanStepMs,
              const std::string& label, const std::string& suffix);
  // Ends the line if one was drawn.
  void finish();

 private:
  std::FILE* out_;
  int width_;
  bool terminal_;
  bool drawn_ = false;
  double lastDraw_ = -1.0;  // elapsed seconds at the last draw
  int lastDecile_ = -1;
};

}  // namespace bcassim
