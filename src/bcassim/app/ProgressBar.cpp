#include "bcassim/app/ProgressBar.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace bcassim {

namespace {
// Below this many seconds a run finishes before a bar would help.
constexpr double kShowAfterSeconds = 1.0;
constexpr double kRedrawSeconds = 0.1;
constexpr int kWidth = 24;

std::string clock(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
                   : fmt::format("{}:{:02}", s / 60, s % 60);
}
}  // namespace

ProgressBar::ProgressBar(std::FILE* out) : out_(out), terminal_(isatty(fileno(out)) != 0) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(const RunProgress& p) {
  if (p.elapsedSeconds < kShowAfterSeconds || p.stepsTotal <= 0) return;
  const double fraction = static_cast<double>(p.stepsDone) / p.stepsTotal;
  const int decile = static_cast<int>(10 * fraction);
  const bool last = p.stepsDone == p.stepsTotal;
  if (terminal_ ? (p.elapsedSeconds - lastDraw_ < kRedrawSeconds && !last) : decile == lastDecile_)
    return;
  lastDraw_ = p.elapsedSeconds;
  lastDecile_ = decile;
  const int filled = static_cast<int>(kWidth * fraction);
  const double eta = fraction > 0 ? p.elapsedSeconds * (1 - fraction) / fraction : 0.0;
  std::string line =
      fmt::format("[{}{}] {:3.0f}% step {}/{}", std::string(filled, '#'),
                  std::string(kWidth - filled, '.'), 100 * fraction, p.step, p.steps);
  if (p.numVariants > 1)
    line += fmt::format(" ({} {}/{})", p.variant, p.variantIndex + 1, p.numVariants);
  line += fmt::format("  elapsed {}  ETA {}  {:.3g} ms/step", clock(p.elapsedSeconds), clock(eta),
                      p.meanStepMs);
  if (terminal_)
    fmt::print(out_, "\r{}\x1b[K", line);
  else
    fmt::print(out_, "{}\n", line);
  std::fflush(out_);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_ && terminal_) fmt::print(out_, "\n");
  drawn_ = false;
}

}  // namespace bcassim
