// The synchronous loop (the runner asks for each step's frame and answers it) and the
// asynchronous one (frames pushed through a LiveEngine: a real-time model answers each at once;
// the engine's filter thread hands frames to the runner, which runs on a thread of its own).
#include "bcassim/navigation/SceneServer.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/live/LiveEngine.h"
#include "bcassim/live/ThreadPriority.h"
#include "bcassim/navigation/FrameIntake.h"
#include "bcassim/navigation/FramePublisher.h"
#include "bcassim/navigation/RealTimeModel.h"

namespace bcassim {

namespace {

// The server with the frames coming in and the answers going out, opened once everything that
// can be set up before the first frame is: frames sent while the filter was still being set up
// waited for it (the first answers on the phantom 167 ms late).
class ServeConnection {
 public:
  ServeConnection(const Scene& scene, const ServeOptions& o, OpenServer openServer,
                  const std::atomic<bool>& interrupted, IgtlServer::Log log)
      : scene_(scene),
        o_(o),
        openServer_(std::move(openServer)),
        interrupted_(interrupted),
        log_(std::move(log)) {}

  void open() {
    if (opened_) return;
    IgtlServer& server = openServer_();
    intake_.emplace(scene_, server, o_.timeOffset, o_.idleTimeout, interrupted_, log_);
    publisher_.emplace(server, *scene_.model.mesh, o_.sendSurface, o_.outDir);
    opened_ = true;
  }
  FrameIntake& intake() {
    open();
    return *intake_;
  }
  FramePublisher& publisher() {
    open();
    return *publisher_;
  }
  void log(const std::string& line) const {
    if (log_) log_(line);
  }
  // Frames received and refused, the camera's period and the latencies into the report.
  void report(ServeReport& r) const {
    if (!opened_) return;
    r.framesReceived = intake_->received();
    r.framesRefused = intake_->skipped();
    r.framePeriodS = intake_->medianFramePeriod();
    r.latencyMs = publisher_->latencyMs();
  }

 private:
  const Scene& scene_;
  const ServeOptions& o_;
  OpenServer openServer_;
  const std::atomic<bool>& interrupted_;
  IgtlServer::Log log_;
  bool opened_ = false;
  std::optional<FrameIntake> intake_;
  std::optional<FramePublisher> publisher_;
};

ServeReport serveSynchronously(const Scene& scene, const ServeOptions& o,
                               ServeConnection& connection) {
  std::optional<IntakeFrame> pending, current;
  AssimilationStream stream;
  // The runner asks for step 1's frame once the filter is set up: the server opens then.
  stream.frame = [&](int step) {
    FrameIntake& intake = connection.intake();
    current.reset();
    if (!pending) {
      pending = intake.next(step - 1);
      if (!pending) return StreamedFrame{StreamedFrame::Kind::End, {}};
    }
    if (pending->step > step) return StreamedFrame{};
    current.swap(pending);  // pending is empty again
    return StreamedFrame{StreamedFrame::Kind::Observed, current->markers};
  };
  stream.publish = [&](const StepPublication& p) {
    std::optional<AnsweredFrame> answered;
    if (current)
      answered = AnsweredFrame{current->step, current->stamp, current->client, current->arrival};
    connection.publisher().publish(p.step, p.time,
                                   current ? current->stamp : connection.intake().stampOf(p.step),
                                   p.hidden, *p.nodePositions, answered);
  };
  stream.notice = [&](const std::string& line) { connection.log(line); };
  ServeReport report;
  report.assimilation = runAssimilation(scene, o.outDir, {}, false, &stream);
  connection.report(report);
  report.lagFrames.assign(report.latencyMs.size(), 0);
  return report;
}

// What passes between the engine's filter thread and the runner's thread: one frame at a time,
// and the analysis of it back.
class RunnerHandoff {
 public:
  // Filter thread: hands over the frame of `step` and waits for its analysis.
  ParameterSet analyse(long step, Eigen::MatrixX3d markers) {
    std::unique_lock<std::mutex> lock(mutex_);
    frame_ = std::make_pair(step, std::move(markers));
    result_.reset();
    changed_.notify_all();
    changed_.wait(lock, [&] { return result_.has_value() || failure_ || ended_; });
    if (failure_) std::rethrow_exception(failure_);
    if (!result_)
      throw NumericalError("live filter: the assimilation ended before step " +
                           std::to_string(step));
    return std::move(*result_);
  }

  // Waits until the runner is set up and asks for its first frame, or has ended (its failure
  // rethrown).
  void waitUntilReady() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return asked_ || ended_; });
    if (failure_) std::rethrow_exception(failure_);
  }

  // Runner thread: the frame for `step`, a step without one, or the end.
  StreamedFrame frame(long step) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!asked_) {
      asked_ = true;
      changed_.notify_all();
    }
    changed_.wait(lock, [&] { return frame_.has_value() || stop_; });
    if (!frame_) return {StreamedFrame::Kind::End, {}};
    if (frame_->first > step) return {};
    observedStep_ = step;
    StreamedFrame out{StreamedFrame::Kind::Observed, std::move(frame_->second)};
    frame_.reset();
    return out;
  }

  // Runner thread: the step's analysis, for the frame waiting on it.
  void published(const StepPublication& p) {
    if (p.step != observedStep_) return;
    ParameterSet set;
    set.mean = p.parameterMean;
    set.covariance = p.parameterStddev.array().square().matrix().asDiagonal();
    set.state.resize(p.nodePositions->size() + p.nodeVelocities->size());
    set.state << *p.nodePositions, *p.nodeVelocities;
    set.extras.resize(static_cast<Eigen::Index>(p.hidden.size()));
    for (size_t i = 0; i < p.hidden.size(); ++i)
      set.extras(static_cast<Eigen::Index>(i)) = p.hidden[i].radius95Total;
    const std::lock_guard<std::mutex> lock(mutex_);
    result_ = std::move(set);
    changed_.notify_all();
  }

  void stop() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    changed_.notify_all();
  }
  // Runner thread, at its end: wakes a filter step still waiting.
  void ended(std::exception_ptr failure) {
    const std::lock_guard<std::mutex> lock(mutex_);
    ended_ = true;
    failure_ = std::move(failure);
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<std::pair<long, Eigen::MatrixX3d>> frame_;
  std::optional<ParameterSet> result_;
  long observedStep_ = -1;  // runner thread only
  bool stop_ = false, ended_ = false, asked_ = false;
  std::exception_ptr failure_;
};

// Model steps the real-time side re-runs at most to continue from an analysed state.
constexpr long kCatchUpSteps = 2;

ServeReport serveAsynchronously(const Scene& scene, const ServeOptions& o,
                                ServeConnection& connection, const std::atomic<bool>& interrupted) {
  const AssimilationSettings& s = *scene.assimilation;
  RealTimeModel model(scene, o.realTimeTangent);
  // The first frozen tangent and the own step's first factorisation before the first frame is
  // read: paid while frames wait, they made the first answers queue behind them.
  model.warmUp();
  const Eigen::Index nodes3 = model.positions().size();

  RunnerHandoff handoff;
  AssimilationStream stream;
  stream.frame = [&](int step) { return handoff.frame(step); };
  stream.publish = [&](const StepPublication& p) { handoff.published(p); };
  stream.notice = [&](const std::string& line) { connection.log(line); };
  ServeReport report;
  std::exception_ptr runnerFailure;
  std::thread runner([&] {
    // The filter runs behind the camera: the real-time step and its tangent builds first.
    yieldToRealTime(10);
    try {
      report.assimilation = runAssimilation(scene, o.outDir, {}, false, &stream);
    } catch (...) {
      runnerFailure = std::current_exception();
    }
    handoff.ended(runnerFailure);
  });

  // The real-time side: frames numbered as pushed; the step and arrival of each, read back by
  // the real-time step on this same thread.
  std::vector<long> stepOfFrame;
  std::optional<IntakeFrame> showing;
  long adopted = -2;
  Eigen::VectorXd radii =
      Eigen::VectorXd::Zero(static_cast<Eigen::Index>(scene.hidden.points.size()));
  ParameterSet prior;
  prior.mean.resize(static_cast<Eigen::Index>(s.parameters.size()));
  prior.covariance = Eigen::MatrixXd::Zero(prior.mean.size(), prior.mean.size());
  for (size_t i = 0; i < s.parameters.size(); ++i) {
    prior.mean(static_cast<Eigen::Index>(i)) = s.parameters[i].mean;
    prior.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) =
        s.parameters[i].stddev * s.parameters[i].stddev;
  }
  const RealTimeStep realTime = [&](const Frame& frame, const ParameterSet& p) {
    if (p.frame != adopted && p.frame >= 0) {
      // The analysed state when catching up from it is cheap; further behind, the parameters
      // only: re-running the lag every frame would make the real-time side as slow as the filter.
      const long analysedStep = stepOfFrame[static_cast<size_t>(p.frame)];
      if (showing->step - analysedStep <= kCatchUpSteps)
        model.adopt(p.mean, p.state.head(nodes3), p.state.tail(p.state.size() - nodes3),
                    static_cast<int>(analysedStep));
      else
        model.adoptParameters(p.mean);
      radii = p.extras;
    }
    adopted = p.frame;
    model.advanceTo(static_cast<int>(showing->step));
    const Eigen::MatrixX3d at = model.hiddenPositions();
    std::vector<HiddenPointPrediction> hidden(static_cast<size_t>(at.rows()));
    for (Eigen::Index i = 0; i < at.rows(); ++i) {
      hidden[static_cast<size_t>(i)].position = at.row(i).transpose();
      hidden[static_cast<size_t>(i)].radius95Total = radii(i);
    }
    const long lag = frame.index - 1 - p.frame;
    connection.publisher().publish(
        showing->step, static_cast<double>(showing->step) * scene.dt(), showing->stamp, hidden,
        model.positions(),
        AnsweredFrame{showing->step, showing->stamp, showing->client, showing->arrival}, lag);
    report.lagFrames.push_back(lag);
  };
  const FilterStep filter = [&](const Frame& frame) {
    if (o.filterDelay > 0)
      std::this_thread::sleep_for(std::chrono::duration<double>(o.filterDelay));
    return handoff.analyse(
        std::lround(frame.time / scene.dt()),
        Eigen::MatrixX3d(
            frame.observations.reshaped(3, frame.observations.size() / 3).transpose()));
  };
  LiveOptions live;
  live.mode = LiveMode::Asynchronous;
  live.maxLagFrames = o.maxLagFrames;
  std::optional<LiveEngine> engine;
  try {
    handoff.waitUntilReady();
    FrameIntake& intake = connection.intake();
    engine.emplace(prior, realTime, filter, live);
    long done = 0;
    while (done < scene.steps && (showing = intake.next(done))) {
      stepOfFrame.push_back(showing->step);
      done = showing->step;
      engine->push(Frame{static_cast<long>(stepOfFrame.size()) - 1,
                         static_cast<double>(showing->step) * scene.dt(),
                         Eigen::VectorXd(showing->markers.transpose().reshaped())});
    }
    // The stream's end lets the filter finish the frames waiting; an interrupt does not.
    const LiveSummary summary =
        engine->finish(interrupted ? FinishMode::DropWaiting : FinishMode::Drain);
    report.framesSkippedByFilter = summary.skipped;
    for (const FrameRecord& r : engine->records())
      report.realTimeMs.push_back(1e3 * r.publishSeconds);
  } catch (...) {
    handoff.stop();
    runner.join();
    throw;
  }
  handoff.stop();
  runner.join();
  if (runnerFailure) std::rethrow_exception(runnerFailure);
  connection.report(report);
  return report;
}

}  // namespace

ServeReport serveScene(const Scene& scene, const ServeOptions& options,
                       const OpenServer& openServer, const std::atomic<bool>& interrupted,
                       const IgtlServer::Log& log) {
  if (!scene.assimilation)
    throw InputError(scene.sourceFile +
                     ": no assimilation: section (see docs/assimilation-format.md)");
  if (options.maxLagFrames < 1)
    throw InputError(fmt::format("--max-lag {}: expected at least 1 frame", options.maxLagFrames));
  ServeConnection connection(scene, options, openServer, interrupted, log);
  return options.mode == ServeMode::Synchronous
             ? serveSynchronously(scene, options, connection)
             : serveAsynchronously(scene, options, connection, interrupted);
}

}  // namespace bcassim
