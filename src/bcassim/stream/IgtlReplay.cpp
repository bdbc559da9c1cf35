#include "bcassim/stream/IgtlReplay.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/stream/IgtlMessages.h"
#include "bcassim/stream/TcpSocket.h"

namespace bcassim {

namespace {

// The answers as they come: stamp and arrival, until the server closes the connection.
struct AnswerLog {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::pair<double, Clock::time_point>> answers;
  bool closed = false;
  std::string error;
};

void readAnswers(const TcpSocket& socket, const std::string& device, AnswerLog& log) {
  unsigned char header[kIgtlHeaderSize];
  std::string body;
  while (socket.readExactly(header, sizeof header)) {
    IgtlHeader h;
    try {
      h = decodeIgtlHeader(header);
    } catch (const InputError& e) {
      const std::lock_guard<std::mutex> lock(log.mutex);
      log.error = e.what();
      break;
    }
    if (h.bodySize > kIgtlMaxBodyBytes) {
      const std::lock_guard<std::mutex> lock(log.mutex);
      log.error = fmt::format("{} '{}' announces a body of {} bytes", h.type, h.device, h.bodySize);
      break;
    }
    body.resize(h.bodySize);
    if (!socket.readExactly(body.data(), body.size())) break;
    if (h.device != device) continue;
    const std::lock_guard<std::mutex> lock(log.mutex);
    log.answers.emplace_back(h.time, Clock::now());
    log.changed.notify_all();
  }
  const std::lock_guard<std::mutex> lock(log.mutex);
  log.closed = true;
  log.changed.notify_all();
}

std::vector<NamedPoint> pointsOf(const Eigen::MatrixX3d& frame) {
  std::vector<NamedPoint> points;
  for (Eigen::Index i = 0; i < frame.rows(); ++i)
    if (frame.row(i).allFinite())
      points.push_back({fmt::format("marker_{}", i), frame.row(i).transpose(), 0.0});
  return points;
}

}  // namespace

ReplayReport replayTracks(const MarkerTracks& tracks, const ReplayOptions& options) {
  if (!(options.rate > 0) || !std::isfinite(options.rate))
    throw InputError(fmt::format("--rate {}: expected frames per second above 0", options.rate));
  TcpSocket socket = TcpSocket::connectTo(options.host, options.port);
  AnswerLog log;
  std::thread reader([&] { readAnswers(socket, options.answerDevice, log); });

  ReplayReport report;
  std::vector<Clock::time_point> sentAt;
  const Clock::time_point start = Clock::now();
  const auto period = std::chrono::duration<double>(1.0 / options.rate);
  for (size_t f = 0; f < tracks.frames.size(); ++f) {
    std::this_thread::sleep_until(
        start + std::chrono::duration_cast<Clock::duration>(period * static_cast<double>(f)));
    const std::string message =
        encodeIgtlPoints(options.device, tracks.times[f], "markers", pointsOf(tracks.frames[f]));
    sentAt.push_back(Clock::now());
    if (!socket.writeAll(message.data(), message.size())) break;
    ++report.sent;
  }
  report.seconds =
      report.sent > 1 ? std::chrono::duration<double>(sentAt.back() - sentAt.front()).count() : 0.0;
  {
    std::unique_lock<std::mutex> lock(log.mutex);
    size_t seen = log.answers.size();
    // Until the server closes, or answers stop coming for waitSeconds.
    while (!log.closed &&
           log.changed.wait_for(lock, std::chrono::duration<double>(options.waitSeconds),
                                [&] { return log.closed || log.answers.size() != seen; })) {
      seen = log.answers.size();
    }
  }
  socket.shutdown();
  reader.join();
  if (!log.error.empty())
    throw InputError(fmt::format("{}:{}: {}", options.host, options.port, log.error));
  report.answers = static_cast<long>(log.answers.size());
  const auto sentTimes = tracks.times.begin();
  const auto sentEnd = sentTimes + static_cast<long>(sentAt.size());
  for (const auto& [stamp, arrived] : log.answers) {
    // The frame with this stamp (times increase; stamps go through OpenIGTLink's 2^-32 s fixed
    // point, hence the tolerance).
    const auto f = std::lower_bound(sentTimes, sentEnd, stamp - 1e-6);
    if (f != sentEnd && std::abs(*f - stamp) < 1e-6)
      report.roundTripMs.push_back(
          1e3 * std::chrono::duration<double>(arrived - sentAt[static_cast<size_t>(f - sentTimes)])
                    .count());
  }
  return report;
}

}  // namespace bcassim
