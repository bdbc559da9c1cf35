// `bcassim serve SCENE` (the scene's assimilation fed live over OpenIGTLink: tracked points in,
// hidden points with their 95 % radius and the deformed surface out, every frame) and `bcassim
// replay TRACKS.csv --to HOST:PORT` (a recorded sequence sent as a camera would). Wires stream/
// to runAssimilation; prints the connection log, the summary and the latency line.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/OutputDirectoryLock.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/OutputFiles.h"
#include "bcassim/scene/SceneLoader.h"
#include "bcassim/stream/IgtlMessages.h"
#include "bcassim/stream/IgtlReplay.h"
#include "bcassim/stream/IgtlServer.h"
#include "bcassim/stream/StepClock.h"

namespace bcassim {
namespace {

std::atomic<bool> gInterrupted{false};
extern "C" void onInterrupt(int /*signal*/) { gInterrupted = true; }

// p-th percentile (0..100) by nearest rank; 0 for none.
double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

std::string latencyLine(const std::vector<double>& ms) {
  return fmt::format("p50 {:.1f} ms, p95 {:.1f} ms, p99 {:.1f} ms, max {:.1f} ms over {} frames",
                     percentile(ms, 50), percentile(ms, 95), percentile(ms, 99),
                     ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()), ms.size());
}

void logLine(const std::string& line) {
  fmt::print(stderr, "serve: {}\n", line);
  std::fflush(stderr);
}

// The stream side of a served run: frames from the server to steps, predictions back.
class ServedRun {
 public:
  ServedRun(const Scene& scene, IgtlServer& server, std::optional<double> timeOffset,
            double idleTimeout, bool sendSurface, const std::filesystem::path& outDir)
      : scene_(scene),
        server_(server),
        clock_(scene.dt(), timeOffset),
        idleTimeout_(idleTimeout),
        sendSurface_(sendSurface),
        latencyPath_(outDir / "latency.csv"),
        latency_(openForWriting(latencyPath_)) {
    latency_ << "step,time_s,frame_stamp_s,client,latency_ms,clients\n";
    flushOrThrow(latency_, latencyPath_);
    if (sendSurface_) {
      const BoundarySurface b = extractBoundary(*scene.model.mesh);
      surfaceNodes_ = b.nodes;
      surfaceFaces_ = toTriMesh(*scene.model.mesh, b).F;
    }
  }

  AssimilationStream stream() {
    return {[this](int step) { return frame(step); },
            [this](const StepPublication& p) { publish(p); }};
  }

  const std::vector<double>& latencyMs() const { return latencyMs_; }
  long dropped() const { return dropped_; }
  long frames() const { return frames_; }

 private:
  struct Pending {
    long step = 0;
    double stamp = 0.0;
    int client = 0;
    Eigen::MatrixX3d markers;
    Clock::time_point arrival;
  };

  StreamedFrame frame(int step) {
    Clock::time_point lastFrame = Clock::now();
    while (!pending_) {
      if (gInterrupted) return {StreamedFrame::Kind::End, {}};
      std::optional<ReceivedFrame> f = server_.nextFrame(std::chrono::milliseconds(200));
      if (!f) {
        if (idleTimeout_ > 0 &&
            std::chrono::duration<double>(Clock::now() - lastFrame).count() > idleTimeout_) {
          logLine(fmt::format("no frame for {:g} s (--idle-timeout); ending at step {}",
                              idleTimeout_, step - 1));
          return {StreamedFrame::Kind::End, {}};
        }
        continue;
      }
      lastFrame = Clock::now();
      ++frames_;
      take(std::move(*f), step);
    }
    if (pending_->step > scene_.steps) {
      logLine(fmt::format("frame at {:.6f} s is step {}, past the scene's {} steps; ending",
                          pending_->stamp, pending_->step, scene_.steps));
      return {StreamedFrame::Kind::End, {}};
    }
    current_.reset();
    if (pending_->step > step) return {StreamedFrame::Kind::Missing, {}};
    current_ = std::move(pending_);
    pending_.reset();
    return {StreamedFrame::Kind::Observed, current_->markers};
  }

  // A received frame into pending_, unless it is malformed or for a step already done.
  void take(ReceivedFrame f, int step) {
    const long k = clock_.stepOf(f.time);
    Pending p;
    try {
      p.markers = markersFromPoints(f.points, static_cast<int>(scene_.markers.points.size()));
    } catch (const InputError& e) {
      logLine(fmt::format("client {}: POINT '{}' at {:.6f} s: {}; frame skipped", f.client,
                          f.device, f.time, e.what()));
      ++dropped_;
      return;
    }
    if (k < step) {
      // Step 0 is the rest state, never analysed; anything else came too late or twice.
      if (k != 0) {
        logLine(
            fmt::format("client {}: frame at {:.6f} s is step {}, already done (now step "
                        "{}); frame skipped",
                        f.client, f.time, k, step));
        ++dropped_;
      }
      return;
    }
    p.step = k;
    p.stamp = f.time;
    p.client = f.client;
    p.arrival = f.arrival;
    pending_ = std::move(p);
  }

  void publish(const StepPublication& p) {
    const double stamp = current_ ? current_->stamp : clock_.stampOf(p.step);
    std::vector<NamedPoint> hidden;
    for (size_t i = 0; i < p.hidden.size(); ++i)
      hidden.push_back(
          {fmt::format("hidden_{}", i), p.hidden[i].position, p.hidden[i].radius95Total});
    std::string message = encodeIgtlPoints("bcassim_hidden", stamp, "bcassim", hidden);
    if (sendSurface_) {
      Eigen::MatrixX3d v(static_cast<Eigen::Index>(surfaceNodes_.size()), 3);
      for (size_t i = 0; i < surfaceNodes_.size(); ++i)
        v.row(static_cast<Eigen::Index>(i)) =
            p.nodePositions->segment<3>(3 * static_cast<Eigen::Index>(surfaceNodes_[i]))
                .transpose();
      message += encodeIgtlSurface("bcassim_surface", stamp, v, surfaceFaces_);
    }
    const int clients = server_.broadcast(message);
    if (!current_) return;
    const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - current_->arrival).count();
    latencyMs_.push_back(ms);
    latency_ << fmt::format("{},{:.9g},{:.9f},{},{:.3f},{}\n", p.step, p.time, current_->stamp,
                            current_->client, ms, clients);
    flushOrThrow(latency_, latencyPath_);
  }

  const Scene& scene_;
  IgtlServer& server_;
  StepClock clock_;
  double idleTimeout_;
  bool sendSurface_;
  std::vector<int> surfaceNodes_;
  Eigen::MatrixX3i surfaceFaces_;
  std::filesystem::path latencyPath_;
  std::ofstream latency_;
  std::optional<Pending> pending_, current_;
  std::vector<double> latencyMs_;
  long dropped_ = 0, frames_ = 0;
};

class ServeCommand : public Command {
 public:
  ServeCommand()
      : Command({"serve"},
                "Assimilate live: tracked points in, hidden points and surface out (OpenIGTLink)") {
  }

  void declare(CLI::App& app) override {
    app.add_option("scene", scenePath_,
                   "Scene with an assimilation: section (tracks: stream, or a file, which is "
                   "not read)")
        ->required();
    addOutOption(app, outDir_);
    app.add_option("--host", host_,
                   "Address to listen on (0.0.0.0: every interface, for another machine)")
        ->capture_default_str();
    app.add_option("--port", port_, "TCP port (18944: 3D Slicer's default; 0: any free one)")
        ->capture_default_str()
        ->check(CLI::Range(0, 65535));
    app.add_option("--time-offset", timeOffset_,
                   "Time stamp of the scene's t = 0, s: 'scene' (observations.time_offset, for "
                   "recorded scene times), 'first' (the first frame is step 1, for a camera's "
                   "clock) or a number")
        ->capture_default_str();
    checkNonNegative(app.add_option("--idle-timeout", idleTimeout_,
                                    "End the run when no frame came for this long, s (0: never)")
                         ->capture_default_str());
    app.add_flag("--no-surface", noSurface_, "Send the hidden points only, not the surface");
  }

  int run() override {
    const io::OutputDirectoryLock lock(outDir_);
    const Scene scene = loadScene(scenePath_);
    if (!scene.assimilation)
      throw InputError(scenePath_ + ": no assimilation: section (see docs/assimilation-format.md)");
    std::optional<double> offset;
    if (timeOffset_ == "scene")
      offset = scene.assimilation->observations.timeOffset;
    else if (timeOffset_ != "first")
      offset = numberOption("--time-offset", timeOffset_);

    createOutputDirectory(outDir_);
    IgtlServer server(host_, port_, logLine);
    fmt::print(
        "serving {} on {}:{} (OpenIGTLink): POINT messages of the {} markers in (mm), per frame "
        "bcassim_hidden (POINT, {} hidden points with their 95 % radius){} out; {} steps of "
        "{:.6g} s -> {}\n",
        scenePath_, host_, server.port(), scene.markers.points.size(), scene.hidden.points.size(),
        noSurface_ ? "" : " and bcassim_surface (POLYDATA)", scene.steps, scene.dt(), outDir_);
    std::fflush(stdout);

    gInterrupted = false;
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
    ServedRun served(scene, server, offset, idleTimeout_, !noSurface_, outDir_);
    const AssimilationStream stream = served.stream();
    const AssimilationResult r = runAssimilation(scene, outDir_, {}, false, &stream);
    server.stop();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);

    fmt::print("served {} steps ({} observed) from {} frames, {} skipped, {} client{} in all\n",
               r.steps, r.observedSteps, served.frames(), served.dropped(), server.clientsEver(),
               server.clientsEver() == 1 ? "" : "s");
    for (const ParameterResult& p : r.parameters)
      fmt::print("  {:<14} {:.6g} ± {:.3g}\n", p.name, p.mean, p.stddev);
    fmt::print("latency (frame arrival -> prediction sent): {}\n", latencyLine(served.latencyMs()));
    fmt::print("filter: median {:.3g} ms/step (mean {:.3g}) -> {}\n", r.medianStepMs, r.meanStepMs,
               outDir_);
    return 0;
  }

 private:
  static double numberOption(const std::string& name, const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
      throw InputError(
          fmt::format("{} '{}': expected 'scene', 'first' or a number of seconds", name, text));
    return v;
  }

  std::string scenePath_, outDir_ = "out/serve", host_ = "127.0.0.1", timeOffset_ = "scene";
  int port_ = 18944;
  double idleTimeout_ = 0.0;
  bool noSurface_ = false;
};

class ReplayCommand : public Command {
 public:
  ReplayCommand()
      : Command({"replay"}, "Send recorded marker tracks to an OpenIGTLink server at a rate") {}

  void declare(CLI::App& app) override {
    app.add_option("tracks", tracksPath_, "Tracks CSV: time,marker,x,y,z (s, m)")->required();
    app.add_option("--to", to_, "The server, HOST:PORT")->required();
    app.add_option("--rate", options_.rate, "Frames per second")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    app.add_option("--device", options_.device, "Device name of the POINT messages")
        ->capture_default_str();
    checkNonNegative(app.add_option("--wait", options_.waitSeconds,
                                    "After the last frame, wait this long for answers, s")
                         ->capture_default_str());
  }

  int run() override {
    const MarkerTracks tracks = readMarkerTracks(tracksPath_);
    splitHostPort(to_, "--to", options_.host, options_.port);
    const ReplayReport r = replayTracks(tracks, options_);
    fmt::print("replayed {} of {} frames in {:.3g} s ({:.3g} Hz) to {}; {} answers\n", r.sent,
               tracks.frames.size(), r.seconds,
               r.seconds > 0 ? static_cast<double>(r.sent - 1) / r.seconds : 0.0, to_, r.answers);
    fmt::print("round trip (frame sent -> its hidden points received): {}\n",
               latencyLine(r.roundTripMs));
    return r.sent == static_cast<long>(tracks.frames.size()) ? 0 : 4;
  }

 private:
  std::string tracksPath_, to_;
  ReplayOptions options_;
};

}  // namespace

std::unique_ptr<Command> makeServeCommand() { return std::make_unique<ServeCommand>(); }
std::unique_ptr<Command> makeReplayCommand() { return std::make_unique<ReplayCommand>(); }

}  // namespace bcassim
