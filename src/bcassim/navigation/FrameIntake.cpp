#include "bcassim/navigation/FrameIntake.h"

#include <fmt/format.h>

#include <algorithm>

#include "bcassim/Error.h"
#include "bcassim/stream/IgtlMessages.h"

namespace bcassim {

FrameIntake::FrameIntake(const Scene& scene, IgtlServer& server, std::optional<double> timeOffset,
                         double idleTimeout, const std::atomic<bool>& interrupted, Log log)
    : scene_(scene),
      server_(server),
      clock_(scene.dt(), timeOffset),
      idleTimeout_(idleTimeout),
      interrupted_(interrupted),
      log_(std::move(log)) {}

std::optional<IntakeFrame> FrameIntake::next(long done) {
  using Clock = std::chrono::steady_clock;
  Clock::time_point waitingSince = Clock::now();
  for (;;) {
    if (interrupted_) return std::nullopt;
    std::optional<ReceivedFrame> f = server_.nextFrame(std::chrono::milliseconds(200));
    if (!f) {
      if (idleTimeout_ > 0 &&
          std::chrono::duration<double>(Clock::now() - waitingSince).count() > idleTimeout_) {
        log_(fmt::format("no frame for {:g} s (--idle-timeout); ending after step {}", idleTimeout_,
                         done));
        return std::nullopt;
      }
      continue;
    }
    waitingSince = Clock::now();
    ++received_;
    IntakeFrame out;
    try {
      out.markers = markersFromPoints(f->points, static_cast<int>(scene_.markers.points.size()));
      // Into the model's frame (observations.frame_transform); markers not sent stay NaN.
      if (scene_.assimilation && scene_.assimilation->observations.frameTransform)
        out.markers = scene_.assimilation->observations.frameTransform->apply(out.markers);
    } catch (const InputError& e) {
      log_(fmt::format("client {}: frame '{}' at {:.6f} s: {}; frame skipped", f->client, f->device,
                       f->time, e.what()));
      ++skipped_;
      continue;
    }
    out.step = clock_.stepOf(f->time);
    if (out.step <= done) {
      // Step 0 is the rest state, never analysed; anything else came too late or twice.
      if (out.step != 0) {
        log_(
            fmt::format("client {}: frame at {:.6f} s is step {}, already done (now after step "
                        "{}); frame skipped",
                        f->client, f->time, out.step, done));
        ++skipped_;
      }
      continue;
    }
    if (out.step > scene_.steps) {
      log_(fmt::format("frame at {:.6f} s is step {}, past the scene's {} steps; ending", f->time,
                       out.step, scene_.steps));
      return std::nullopt;
    }
    out.stamp = f->time;
    out.client = f->client;
    out.arrival = f->arrival;
    arrivals_.push_back(f->arrival);
    return out;
  }
}

double FrameIntake::medianFramePeriod() const {
  if (arrivals_.size() < 2) return 0.0;
  std::vector<double> d;
  for (size_t i = 1; i < arrivals_.size(); ++i)
    d.push_back(std::chrono::duration<double>(arrivals_[i] - arrivals_[i - 1]).count());
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace bcassim
