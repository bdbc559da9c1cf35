#include "bcassim/app/AssimilationProgressBar.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace bcassim {

namespace {
constexpr double kShowAfterSeconds = 1.0;  // shorter runs end before a bar would help
constexpr double kRedrawSeconds = 0.1;
constexpr int kWidth = 20;

std::string clock(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
                   : fmt::format("{}:{:02}", s / 60, s % 60);
}
}  // namespace

AssimilationProgressBar::AssimilationProgressBar(std::FILE* out)
    : out_(out), terminal_(isatty(fileno(out)) != 0) {}

AssimilationProgressBar::~AssimilationProgressBar() { finish(); }

void AssimilationProgressBar::update(const AssimilationProgress& p) {
  if (p.elapsedSeconds < kShowAfterSeconds || p.steps <= 0) return;
  const double fraction = static_cast<double>(p.step) / p.steps;
  const int decile = static_cast<int>(10 * fraction);
  const bool last = p.step == p.steps;
  if (terminal_ ? (p.elapsedSeconds - lastDraw_ < kRedrawSeconds && !last) : decile == lastDecile_)
    return;
  lastDraw_ = p.elapsedSeconds;
  lastDecile_ = decile;
  const int filled = static_cast<int>(kWidth * fraction);
  const double eta = fraction > 0 ? p.elapsedSeconds * (1 - fraction) / fraction : 0.0;
  const std::string line =
      fmt::format("[{}{}] {:3.0f}% step {}/{}{}  {} ETA {}  {:.3g} ms/step  {}",
                  std::string(filled, '#'), std::string(kWidth - filled, '.'), 100 * fraction,
                  p.step, p.steps, p.freeRun ? " (free run)" : "", clock(p.elapsedSeconds),
                  clock(eta), p.meanStepMs, p.estimate);
  if (terminal_)
    fmt::print(out_, "\r{}\x1b[K", line);
  else
    fmt::print(out_, "{}\n", line);
  std::fflush(out_);
  drawn_ = true;
}

void AssimilationProgressBar::finish() {
  if (drawn_ && terminal_) fmt::print(out_, "\n");
  drawn_ = false;
}

}  // namespace bcassim
