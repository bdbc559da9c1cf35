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
#include "bcassim/navigation/SceneServer.h"
#include "bcassim/run/AssimilationRunner.h"
#include "bcassim/run/OutputFiles.h"
#include "bcassim/scene/SceneLoader.h"
#include "bcassim/stream/IgtlReplay.h"
#include "bcassim/stream/IgtlServer.h"

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
    app.add_flag("--no-validation", noValidation_,
                 "Skip the scene's validation (assimilation.validation: a forward run with the "
                 "initial parameters and errors.csv, one more model step after each answer, "
                 "before the next frame is read): for a camera with no truth, or for latency");
    app.add_flag("--async", async_,
                 "Answer every frame at once from a real-time model with the latest analysis; "
                 "the filter runs behind on its own thread (one sigma-point thread)");
    checkNonNegative(app.add_option("--filter-delay", filterDelay_,
                                    "--async: the filter waits this long before each frame, s "
                                    "(to see a filter slower than the camera; 0 in use)")
                         ->capture_default_str());
    app.add_option("--real-time-step", realTimeStep_,
                   "--async: how the real-time model steps: frozen (a stiffness at most 5 "
                   "frames old, built on a thread of its own: one force assembly and one solve "
                   "per frame) or own (its own stiffness assembled and solved every frame, ~4x "
                   "slower, no build thread)")
        ->check(CLI::IsMember({"frozen", "own"}))
        ->capture_default_str();
    app.add_option("--max-lag", maxLag_,
                   "--async: frames that may wait for the filter before the oldest are skipped")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
  }

  int run() override {
    const io::OutputDirectoryLock lock(outDir_);
    // A bad --time-offset is reported before the scene is read.
    const std::optional<double> offsetSeconds =
        timeOffset_ == "scene" || timeOffset_ == "first"
            ? std::nullopt
            : std::optional<double>(numberOption("--time-offset", timeOffset_));
    Scene scene = loadScene(scenePath_);
    if (!scene.assimilation)
      throw InputError(scenePath_ + ": no assimilation: section (see docs/assimilation-format.md)");
    if (noValidation_) scene.assimilation->validationTruth.reset();
    ServeOptions options;
    options.outDir = outDir_;
    options.idleTimeout = idleTimeout_;
    options.sendSurface = !noSurface_;
    options.maxLagFrames = maxLag_;
    options.filterDelay = filterDelay_;
    options.realTimeTangent =
        realTimeStep_ == "own" ? RealTimeTangent::Own : RealTimeTangent::Frozen;
    options.mode = async_ ? ServeMode::Asynchronous : ServeMode::Synchronous;
    if (timeOffset_ == "scene")
      options.timeOffset = scene.assimilation->observations.timeOffset;
    else if (timeOffset_ == "first")
      options.timeOffset.reset();
    else
      options.timeOffset = offsetSeconds;
    // The real-time model has the other core to itself.
    if (async_) {
      scene.assimilation->threads = 1;
      scene.assimilation->tangentInBackground = false;  // a third thread on two cores
      scene.assimilation->tangentBackgroundSteps = 0;
    }

    createOutputDirectory(outDir_);
    gInterrupted = false;
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
    // The port opens, and the line announcing it is printed, once the filter is set up.
    std::optional<IgtlServer> server;
    const OpenServer openServer = [&]() -> IgtlServer& {
      server.emplace(host_, port_, logLine);
      fmt::print(
          "serving {} on {}:{} (OpenIGTLink): POINT messages of the {} markers in (mm), per frame "
          "bcassim_hidden (POINT, {} hidden points with their 95 % radius){} out; {} steps of "
          "{:.6g} s -> {}\n",
          scenePath_, host_, server->port(), scene.markers.points.size(),
          scene.hidden.points.size(), noSurface_ ? "" : " and bcassim_surface (POLYDATA)",
          scene.steps, scene.dt(), outDir_);
      std::fflush(stdout);
      return *server;
    };
    const ServeReport report = serveScene(scene, options, openServer, gInterrupted, logLine);
    if (server) server->stop();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    const AssimilationResult& r = report.assimilation;
    fmt::print("served {} steps ({} observed) from {} frames, {} refused, {} client{} in all\n",
               r.steps, r.observedSteps, report.framesReceived, report.framesRefused,
               server ? server->clientsEver() : 0, server && server->clientsEver() == 1 ? "" : "s");
    for (const ParameterResult& p : r.parameters)
      fmt::print("  {:<14} {:.6g} ± {:.3g}\n", p.name, p.mean, p.stddev);
    fmt::print("latency (frame arrival -> prediction sent): {}\n", latencyLine(report.latencyMs));
    if (options.mode == ServeMode::Asynchronous) {
      const std::vector<double> lag(report.lagFrames.begin(), report.lagFrames.end());
      fmt::print(
          "asynchronous: real-time step p50 {:.1f} ms, p99 {:.1f} ms; filter lag p50 {:.0f}, p99 "
          "{:.0f}, max {:.0f} frames; {} frames skipped by the filter on purpose\n",
          percentile(report.realTimeMs, 50), percentile(report.realTimeMs, 99), percentile(lag, 50),
          percentile(lag, 99), percentile(lag, 100), report.framesSkippedByFilter);
    }
    // The frame period over the filter's mean step: above 1, the filter keeps up with the camera.
    const double factor = r.meanStepMs > 0 ? 1e3 * report.framePeriodS / r.meanStepMs : 0.0;
    fmt::print(
        "filter: median {:.3g} ms/step (mean {:.3g}), real-time factor {:.2f} at {:.3g} Hz -> {}\n",
        r.medianStepMs, r.meanStepMs, factor,
        report.framePeriodS > 0 ? 1.0 / report.framePeriodS : 0.0, options.outDir);
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
  double idleTimeout_ = 0.0, filterDelay_ = 0.0;
  std::string realTimeStep_ = "frozen";
  bool noSurface_ = false, noValidation_ = false, async_ = false;
  int maxLag_ = 8;
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
