#include "bcassim/run/SimulationRunner.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/CsvTruncate.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/PvdSeries.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/run/SimulationCheckpoint.h"
#include "bcassim/run/StressField.h"

namespace bcassim {

namespace {

std::ofstream openForWriting(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  std::ofstream out(path);
  if (!out) io::throwWriteError(path);
  return out;
}

Eigen::MatrixX3d pointPositions(const Scene& scene, const MarkerSet& set,
                                const Eigen::VectorXd& x) {
  Eigen::MatrixX3d P(set.points.size(), 3);
  for (size_t i = 0; i < set.points.size(); ++i)
    P.row(i) = interpolate(set.points[i], *scene.model.mesh, x).transpose();
  return P;
}

Eigen::MatrixX3d markerPositions(const Scene& scene, const Eigen::VectorXd& x) {
  return pointPositions(scene, scene.markers, x);
}

// One ParaView frame: the mesh with displacement and stress, and the markers and springs parts.
void writeFrame(const Scene& scene, const StressField& stress, const MechanicalState& state,
                const Eigen::MatrixX3d& markers, PvdSeries& series) {
  const MechanicalModel& model = scene.model;
  const TetMesh& mesh = *model.mesh;
  const Eigen::VectorXd u = state.x - model.restPositions();
  const Eigen::MatrixX3d U =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          u.data(), mesh.numNodes(), 3);
  FieldSet fields;
  fields.pointVectors.emplace_back("displacement_m", U);
  fields.pointScalars.emplace_back("displacement_magnitude_m", U.rowwise().norm());
  fields.cellScalars.emplace_back("von_mises_Pa", stress.vonMises(mesh, model.elasticity, state.x));
  series.addFrame(state.t, mesh, state.x, fields);
  if (markers.rows() > 0) series.addPoints("markers", markers);
  const auto& springs = model.springs.springs();
  if (!springs.empty()) {
    const Eigen::Index n = static_cast<Eigen::Index>(springs.size());
    Eigen::MatrixX3d points(2 * n, 3);
    Eigen::MatrixX2i segments(n, 2);
    Eigen::VectorXd tension(n);
    for (Eigen::Index s = 0; s < n; ++s) {
      const CubicSpring& spring = springs[s];
      const Vec3 a = model.springs.attachment(mesh, state.x, s);
      points.row(2 * s) = a.transpose();
      points.row(2 * s + 1) = spring.anchor.transpose();
      segments.row(s) << static_cast<int>(2 * s), static_cast<int>(2 * s + 1);
      const double dl = (a - spring.anchor).norm() - spring.restLength;
      tension(s) =
          CubicSpringSet::magnitude(model.springs.activeCoefficients(spring.group, state.t), dl);
    }
    FieldSet springFields;
    springFields.cellScalars.emplace_back("tension_N", tension);
    series.addPolyLines("springs", points, segments, springFields);
  }
}

struct RunTrace {
  RunResult result;
  // At the output steps (every output.every steps and the last), #markers by 3, m; kept only
  // when variants are compared, as it may be large.
  std::map<int, Eigen::MatrixX3d> markerDisplacements;
};

// What a checkpoint must match: the sizes, the time step and the integrator.
std::string checkpointKey(const Scene& scene) {
  return fmt::format("nodes {} tets {} dt {:.17g} {}", scene.model.mesh->numNodes(),
                     scene.model.mesh->numTets(), scene.dt(),
                     scene.integrator == IntegratorKind::Static ? "static" : "implicit-euler");
}

RunTrace runOne(const Scene& scene, const std::string& dir, bool keepMarkers, RunProgress progress,
                Clock::time_point started, const ProgressCallback& callback, bool resume) {
  const Clock::time_point t0 = Clock::now();
  const MechanicalModel& model = scene.model;
  const bool statics = scene.integrator == IntegratorKind::Static;
  RunTrace trace;
  trace.result.name = scene.name;
  trace.result.outDir = dir;
  trace.result.steps = scene.steps;

  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create directory (" + ec.message() + ")");
  MechanicalState state = model.restState();
  SimulationCheckpoint resumed;
  if (resume) {
    resumed = readSimulationCheckpoint(dir, checkpointKey(scene));
    if (resumed.x.size() != state.x.size())
      throw InputError(fmt::format("{}/checkpoint.bin: {} positions, the scene has {}", dir,
                                   resumed.x.size(), state.x.size()));
    state.x = resumed.x;
    state.v = resumed.v;
    state.t = resumed.t;
    trace.result.maxNodeDisplacement = resumed.maxNodeDisplacement;
    trace.result.maxMarkerDisplacement = resumed.maxMarkerDisplacement;
  }
  std::unique_ptr<ImplicitEuler> dynamics;
  std::unique_ptr<StaticSolver> equilibrium;
  auto solver = makeLinearSolver(scene.solver.type, scene.solver.policy);
  if (statics)
    equilibrium = std::make_unique<StaticSolver>(model, std::move(solver), scene.statics);
  else
    dynamics = std::make_unique<ImplicitEuler>(model, std::move(solver), scene.implicitEuler);

  const StressField stress(*model.mesh);
  const std::filesystem::path out(dir);
  std::unique_ptr<PvdSeries> series;
  if (scene.output.pvd) {
    if (resume) {
      series = std::make_unique<PvdSeries>(PvdSeries::resume(dir, "simulation", resumed.frames));
    } else {
      series = std::make_unique<PvdSeries>(dir, "simulation");
      writeFrame(scene, stress, state, markerPositions(scene, state.x), *series);
    }
  }
  // A resumed run keeps the rows up to the checkpoint's time and appends.
  auto trackWriter = [&](const char* name) {
    const std::string path = (out / name).string();
    return resume ? std::make_unique<MarkerTrackWriter>(path, resumed.t)
                  : std::make_unique<MarkerTrackWriter>(path);
  };
  const std::unique_ptr<MarkerTrackWriter> tracks = trackWriter("markers.csv");
  // The validation points' truth for assimilation runs; frame 0 (rest) gives their displacements.
  std::unique_ptr<MarkerTrackWriter> validation;
  if (!scene.validation.points.empty()) {
    validation = trackWriter("validation.csv");
    if (!resume) validation->write(state.t, pointPositions(scene, scene.validation, state.x));
  }
  std::unique_ptr<MarkerTrackWriter> hidden;
  if (!scene.hidden.points.empty()) {
    hidden = trackWriter("hidden.csv");
    if (!resume) hidden->write(state.t, pointPositions(scene, scene.hidden, state.x));
  }
  const std::string timingPath = (out / "timing.csv").string();
  std::ofstream timing =
      openStepCsv(timingPath,
                  statics ? "step,time_s,total_ms,newton_iterations"
                          : "step,time_s,assembly_ms,solve_ms,total_ms,linear_iterations",
                  resume ? std::optional<double>(resumed.step) : std::nullopt);

  const Eigen::VectorXd rest = model.restPositions();
  double stepSeconds = resume ? resumed.stepSeconds : 0.0;
  progress.step = resumed.step;
  for (int step = resumed.step + 1; step <= scene.steps; ++step) {
    const Clock::time_point s0 = Clock::now();
    if (statics) {
      state.t = step * scene.dt();
      const StaticReport report = equilibrium->solve(model, state.t, state.x);
      if (!report.converged)
        throw NumericalError(fmt::format(
            "{}: static equilibrium not reached at t = {:.6g} s (step {}): residual {:.3g} N after "
            "{} Newton iterations",
            scene.sourceFile, state.t, step, report.residualNorm, report.iterations));
      const double s = secondsSince(s0);
      stepSeconds += s;
      timing << fmt::format("{},{:.9g},{:.6g},{}\n", step, state.t, 1e3 * s, report.iterations);
    } else {
      dynamics->step(model, state);
      state.t = step * scene.dt();  // no drift from summing dt over thousands of steps
      stepSeconds += secondsSince(s0);
      const StepTimings& tm = dynamics->lastTimings();
      timing << fmt::format("{},{:.9g},{:.6g},{:.6g},{:.6g},{}\n", step, state.t, 1e3 * tm.assembly,
                            1e3 * tm.solve, 1e3 * tm.total, tm.lastSolve.iterations);
    }
    for (Eigen::Index i = 0; i < model.mesh->numNodes(); ++i)
      trace.result.maxNodeDisplacement =
          std::max(trace.result.maxNodeDisplacement,
                   (state.x.segment<3>(3 * i) - rest.segment<3>(3 * i)).norm());
    const Eigen::MatrixX3d markers = markerPositions(scene, state.x);
    tracks->write(state.t, markers);
    if (validation) validation->write(state.t, pointPositions(scene, scene.validation, state.x));
    if (hidden) hidden->write(state.t, pointPositions(scene, scene.hidden, state.x));
    const Eigen::MatrixX3d u = markers - scene.markers.rest;
    if (u.rows() > 0)
      trace.result.maxMarkerDisplacement =
          std::max(trace.result.maxMarkerDisplacement, u.rowwise().norm().maxCoeff());
    const bool outputStep = step % scene.output.every == 0 || step == scene.steps;
    if (keepMarkers && outputStep) trace.markerDisplacements.emplace(step, u);
    if (series && outputStep) writeFrame(scene, stress, state, markers, *series);
    if (outputStep) {  // everything up to this step is on disk: a run stopped later resumes here
      timing.flush();
      SimulationCheckpoint c;
      c.step = step;
      c.t = state.t;
      c.x = state.x;
      c.v = state.v;
      c.frames = series ? series->numFrames() : 0;
      c.maxNodeDisplacement = trace.result.maxNodeDisplacement;
      c.maxMarkerDisplacement = trace.result.maxMarkerDisplacement;
      c.stepSeconds = stepSeconds;
      writeSimulationCheckpoint(dir, checkpointKey(scene), c);
    }

    progress.step = step;
    ++progress.stepsDone;
    progress.elapsedSeconds = secondsSince(started);
    progress.meanStepMs = 1e3 * stepSeconds / step;
    if (callback) callback(progress);
  }
  timing.flush();
  if (!timing) io::throwWriteError(dir + "/timing.csv");
  trace.result.frames = series ? series->numFrames() : 0;
  trace.result.meanStepMs = scene.steps > 0 ? 1e3 * stepSeconds / scene.steps : 0.0;
  trace.result.wallSeconds = secondsSince(t0);
  return trace;
}

// max over rows of |a - b|, and of |a|.
double maxRowDistance(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
  return a.rows() ? (a - b).rowwise().norm().maxCoeff() : 0.0;
}
double maxRowNorm(const Eigen::MatrixX3d& a) {
  return a.rows() ? a.rowwise().norm().maxCoeff() : 0.0;
}

double ratio(double num, double den) {
  if (den > 0) return num / den;
  return num > 0 ? std::numeric_limits<double>::infinity() : 0.0;
}

// Compares at the output steps both runs kept; the last step is one of them.
void compareWithBase(const RunTrace& base, RunTrace& run) {
  if (base.markerDisplacements.empty() || run.markerDisplacements.empty()) return;
  double diffAll = 0, refAll = 0;
  for (const auto& [step, ref] : base.markerDisplacements) {
    const auto it = run.markerDisplacements.find(step);
    if (it == run.markerDisplacements.end()) continue;
    diffAll = std::max(diffAll, maxRowDistance(it->second, ref));
    refAll = std::max(refAll, maxRowNorm(ref));
  }
  const Eigen::MatrixX3d& refFinal = base.markerDisplacements.rbegin()->second;
  const Eigen::MatrixX3d& final = run.markerDisplacements.rbegin()->second;
  run.result.relativeDifferenceFinal = ratio(maxRowDistance(final, refFinal), maxRowNorm(refFinal));
  run.result.relativeDifferenceAll = ratio(diffAll, refAll);
}

}  // namespace

SimulationResult runSimulation(const Scene& scene, const std::string& outDir,
                               const ProgressCallback& progress, bool resume) {
  const Clock::time_point started = Clock::now();
  if (resume && !scene.variants.empty())
    throw InputError(scene.sourceFile + ": --resume: not for scenes with variants (run again)");
  std::vector<const Scene*> scenes = {&scene};
  for (const Scene& v : scene.variants) scenes.push_back(&v);

  RunProgress p;
  p.numVariants = static_cast<int>(scenes.size());
  for (const Scene* s : scenes) p.stepsTotal += s->steps;

  SimulationResult result;
  RunTrace base;
  for (size_t i = 0; i < scenes.size(); ++i) {
    p.variant = scenes[i]->name;
    p.variantIndex = static_cast<int>(i);
    p.steps = scenes[i]->steps;
    p.step = 0;
    const std::string dir =
        i == 0 ? outDir : (std::filesystem::path(outDir) / scenes[i]->name).string();
    RunTrace trace = runOne(*scenes[i], dir, scenes.size() > 1, p, started, progress, resume);
    p.stepsDone += scenes[i]->steps;
    if (i == 0)
      base = trace;
    else
      compareWithBase(base, trace);
    result.runs.push_back(trace.result);
  }

  if (!scene.variants.empty()) {
    const std::string path = (std::filesystem::path(outDir) / "variants.csv").string();
    std::ofstream csv = openForWriting(path);
    csv << "name,max_rel_diff_final,max_rel_diff_all,mean_step_ms,max_marker_displacement_m\n";
    for (const RunResult& r : result.runs)
      csv << fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g}\n", r.name, r.relativeDifferenceFinal,
                         r.relativeDifferenceAll, r.meanStepMs, r.maxMarkerDisplacement);
    csv.flush();
    if (!csv) io::throwWriteError(path);
  }
  result.wallSeconds = secondsSince(started);
  return result;
}

}  // namespace bcassim
