#include "bcassim/cli/ProgressLine.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace bcassim {

namespace {
constexpr double kShowAfterSeconds = 1.0;  // shorter runs end before a bar would help
constexpr double kRedrawSeconds = 0.1;

std::string clock(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
                   : fmt::format("{}:{:02}", s / 60, s % 60);
}
}  // namespace

ProgressLine::ProgressLine(std::FILE* out, int width)
    : out_(out), width_(width), terminal_(isatty(fileno(out)) != 0) {}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::update(long done, long total, double elapsed, double meanStepMs,
                          const std::string& label, const std::string& suffix) {
  if (elapsed < kShowAfterSeconds || total <= 0) return;
  const double fraction = static_cast<double>(done) / total;
  const int decile = static_cast<int>(10 * fraction);
  const bool last = done == total;
  if (terminal_ ? (elapsed - lastDraw_ < kRedrawSeconds && !last) : decile == lastDecile_) return;
  lastDraw_ = elapsed;
  lastDecile_ = decile;
  const int filled = static_cast<int>(width_ * fraction);
  const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0.0;
  const std::string line =
      fmt::format("[{}{}] {:3.0f}% step {}/{}{}  elapsed {}  ETA {}  {:.3g} ms/step{}",
                  std::string(filled, '#'), std::string(width_ - filled, '.'), 100 * fraction, done,
                  total, label, clock(elapsed), clock(eta), meanStepMs, suffix);
  if (terminal_)
    fmt::print(out_, "\r{}\x1b[K", line);
  else
    fmt::print(out_, "{}\n", line);
  std::fflush(out_);
  drawn_ = true;
}

void ProgressLine::finish() {
  if (drawn_ && terminal_) fmt::print(out_, "\n");
  drawn_ = false;
}

}  // namespace bcassim
