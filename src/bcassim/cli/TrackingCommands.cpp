// `bcassim track DETECTIONS` and `bcassim register MODEL POINTS`: intra-operative points before
// they meet the model (thesis §5.3): identities of unlabelled detections over frames, and the
// rigid pose of a point set on the model (Kabsch with correspondences, ICP without).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/DetectionsCsv.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/IndexListReader.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/PointCsvWriter.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/PointSetAlignment.h"
#include "bcassim/tracking/LabelledTracks.h"
#include "bcassim/tracking/MarkerTracker.h"
#include "bcassim/tracking/PointCloudUnits.h"
#include "bcassim/tracking/SurfaceRegistration.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// track

// Which frames MarkerTracker takes (a finite time later than the last one taken); the others it
// skips and reports.
std::vector<char> framesTaken(const std::vector<TimedPoints>& frames) {
  std::vector<char> taken(frames.size(), 0);
  std::optional<double> last;
  for (size_t f = 0; f < frames.size(); ++f) {
    const double t = frames[f].time;
    if (!std::isfinite(t) || (last && t <= *last)) continue;
    taken[f] = 1;
    last = t;
  }
  return taken;
}

class TrackCommand : public Command {
 public:
  TrackCommand()
      : Command({"track"},
                "Identities of unlabelled marker detections over frames: raw detections CSV -> "
                "labelled tracks CSV") {}

  void declare(CLI::App& app) override {
    app.add_option("DETECTIONS", detections_,
                   "Raw detections CSV: time,x,y,z rows (s, m), several per frame, no ids")
        ->required();
    addOutOption(app, out_);
    app.add_option("--gate", options_.gate,
                   "Largest distance (m) from a marker's predicted position to a detection "
                   "paired with it")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--confirm-frames", options_.confirmFrames,
                   "Consecutive frames a new marker must be seen in before it gets an id (a "
                   "spurious detection never is)")
        ->check(CLI::Range(1, 1000000))
        ->capture_default_str();
    app.add_option("--max-missed", options_.maxMissedFrames,
                   "Frames a lost marker keeps its id while unseen (then its track ends)")
        ->check(CLI::Range(0, 1000000))
        ->capture_default_str();
    app.add_option("--method", method_,
                   "Pairing of detections with markers: optimal (global assignment) or greedy "
                   "(the thesis' minimal distances first, the baseline)")
        ->check(CLI::IsMember({"optimal", "greedy"}))
        ->capture_default_str();
    app.add_option("--noise", options_.measurementNoise,
                   "Standard deviation of a detection's coordinates (m), for the motion "
                   "prediction")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
  }

  int run() override {
    options_.assignment =
        method_ == "greedy" ? AssignmentMethod::Greedy : AssignmentMethod::Optimal;
    const std::vector<TimedPoints> frames = readDetectionsCsv(detections_);
    std::vector<DetectionFrame> input;
    input.reserve(frames.size());
    for (const TimedPoints& f : frames) input.push_back({f.time, f.points});
    const TrackingResult result = trackMarkers(input, options_);

    const fs::path out(out_);
    fs::create_directories(out);
    const std::string tracksPath = (out / "tracks.csv").string();
    writeMarkerTracks(tracksPath, labelledTracks(input, result));
    const std::vector<char> taken = framesTaken(frames);
    long detections = 0, labelled = 0, spurious = 0, bad = 0;
    int badFrames = 0;
    for (size_t f = 0; f < frames.size(); ++f) {
      const Eigen::MatrixX3d& points = frames[f].points;
      detections += points.rows();
      bool badInput = !taken[f] || points.rows() == 0;
      for (Eigen::Index j = 0; j < points.rows(); ++j) {
        if (result.ids[f][j] >= 0) {
          ++labelled;
        } else if (taken[f] && points.row(j).allFinite()) {
          ++spurious;
        } else {
          ++bad;
          badInput = true;
        }
      }
      badFrames += badInput;
    }
    fmt::print("frames: {} ({} with bad input), detections: {}\n", frames.size(), badFrames,
               detections);
    fmt::print("tracks confirmed: {}\n", result.tracks.size());
    fmt::print("detections labelled: {}\n", labelled);
    fmt::print("detections dropped as spurious (no confirmed track): {}\n", spurious);
    fmt::print("detections dropped as bad input: {}\n", bad);
    for (const std::string& line : result.report) fmt::print("bad input: {}\n", line);
    fmt::print("wrote {} (time,marker,x,y,z: s, id, m; a marker not seen has no row)\n",
               tracksPath);
    return 0;
  }

 private:
  std::string detections_, out_ = "out/track", method_ = "optimal";
  TrackerOptions options_;
};

// ---------------------------------------------------------------------------------------------
// register

// The model as registration sees it: its boundary surface (the target of ICP) and all its
// nodes (what --model-ids names), in metres.
struct RegistrationModel {
  TriMesh surface;
  Eigen::MatrixX3d nodes;
};

// The DATASET line of a legacy VTK file (its header is text even in binary files).
bool isLegacyVtkPolyData(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  for (int i = 0; i < 6 && std::getline(in, line); ++i)
    if (line.rfind("DATASET", 0) == 0) return line.find("POLYDATA") != std::string::npos;
  return false;
}

RegistrationModel readRegistrationModel(const std::string& path, double scale) {
  if (!fs::is_regular_file(path)) throw InputError(path + ": cannot open file");
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  RegistrationModel m;
  if (ext == ".vtu" || ext == ".msh" || ext == ".mesh" ||
      (ext == ".vtk" && !isLegacyVtkPolyData(path))) {
    const TetMesh mesh = readTetMesh(path);
    m.surface = toTriMesh(mesh, extractBoundary(mesh));
    m.nodes = mesh.V;
  } else if (ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".vtp" || ext == ".vtk") {
    m.surface = readSurface(path);
    if (m.surface.F.rows() == 0)
      throw InputError(path + ": no triangles; expected a closed or partial organ surface");
    m.nodes = m.surface.V;
  } else {
    throw InputError(
        fmt::format("{}: unsupported model format '{}'; expected a tet mesh (.vtu, .msh, .mesh, "
                    ".vtk) or a triangle "
                    "surface (.obj, .stl, .ply, .vtp, .vtk)",
                    path, ext));
  }
  m.surface.V *= scale;
  m.nodes *= scale;
  return m;
}

// A CSV whose first line is the tracks header (io/CsvTracks.h).
bool isTracksCsv(const std::string& path) {
  if (fs::path(path).extension() != ".csv") return false;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    return line == "time,marker,x,y,z";
  }
  return false;
}

// The points to register: rows of a point file, or the markers of one frame of a tracks CSV
// (row m is marker m, NaN when it was not seen then).
struct PointsToRegister {
  Eigen::MatrixX3d points;
  bool fromTracks = false;
  double time = 0.0;  // s, of the tracks frame
};

PointsToRegister readPointsToRegister(const std::string& path, std::optional<double> time) {
  PointsToRegister p;
  if (!isTracksCsv(path)) {
    if (time)
      throw InputError(
          fmt::format("--time {} s: {} is not a tracks CSV (time,marker,x,y,z); expected "
                      "--time only with one",
                      *time, path));
    p.points = readPoints(path);
    return p;
  }
  const MarkerTracks tracks = readMarkerTracks(path);
  p.fromTracks = true;
  size_t frame = 0;
  if (time) {
    frame = tracks.times.size();
    for (size_t f = 0; f < tracks.times.size(); ++f)
      if (std::abs(tracks.times[f] - *time) <= 1e-9 * std::max(1.0, std::abs(*time))) frame = f;
    if (frame == tracks.times.size())
      throw InputError(
          fmt::format("{}: no frame at time {} s; expected one of its times ({} .. {} s)", path,
                      *time, tracks.times.front(), tracks.times.back()));
  }
  p.points = tracks.frames[frame];
  p.time = tracks.times[frame];
  return p;
}

Eigen::MatrixX3d finiteRows(const Eigen::MatrixX3d& P, std::vector<int>* kept = nullptr) {
  std::vector<int> rows;
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (P.row(i).allFinite()) rows.push_back(static_cast<int>(i));
  Eigen::MatrixX3d out(static_cast<Eigen::Index>(rows.size()), 3);
  for (size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = P.row(rows[k]);
  if (kept) *kept = std::move(rows);
  return out;
}

void writeTransform(const fs::path& out, const RigidTransform& t) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = t.rotation;
  M.topRightCorner<3, 1>() = t.translation;
  for (const auto& [file, separator] :
       {std::pair<const char*, const char*>{"transform.csv", ","}, {"transform.txt", " "}}) {
    const fs::path path = out / file;
    std::ofstream f(path);
    for (int r = 0; r < 4; ++r)
      f << fmt::format("{:.17g}{}{:.17g}{}{:.17g}{}{:.17g}\n", M(r, 0), separator, M(r, 1),
                       separator, M(r, 2), separator, M(r, 3));
    if (!f) io::throwWriteError(path.string());
  }
}

// A number in (0, 1].
const CLI::Validator kFraction(
    [](const std::string& text) -> std::string {
      double v = 0.0;
      try {
        size_t used = 0;
        v = std::stod(text, &used);
        if (used != text.size()) v = -1.0;
      } catch (const std::exception&) {
        v = -1.0;
      }
      return v > 0.0 && v <= 1.0 ? ""
                                 : fmt::format("expected a fraction in (0, 1], got '{}'", text);
    },
    "FRACTION");

class RegisterCommand : public Command {
 public:
  RegisterCommand()
      : Command({"register"},
                "Rigid pose of a point set on a model: Kabsch with correspondences, trimmed "
                "point-to-plane ICP from several starts without") {}

  void declare(CLI::App& app) override {
    app.add_option(
           "MODEL", model_,
           "Model: a tet mesh (.vtu, .msh, .mesh, .vtk), whose boundary is the target, or a "
           "triangle surface (.obj, .stl, .ply, .vtp, .vtk)")
        ->required();
    app.add_option("POINTS", points_,
                   "Points in their own frame (m): .csv (x,y,z), .txt (x y z), .npy (N x 3), "
                   ".ply (an RGB-D export's vertices), .vtp/.vtu/.vtk (their points), or one "
                   "frame of a tracks CSV (time,marker,x,y,z; --time)")
        ->required();
    addOutOption(app, out_);
    addScaleOption(app, scale_);
    app.add_option("--time", time_, "Frame of a tracks CSV to register (s; default: its first)");
    auto* pairs = app.add_option(
        "--pairs", pairs_,
        "Correspondences: the model-frame positions (m, a point file) of POINTS' rows, row by "
        "row (a tracks frame: row m is marker m); Kabsch instead of ICP");
    app.add_option("--model-ids", modelIds_,
                   "Correspondences: the model node (tet mesh) or vertex (surface) id of each row "
                   "of POINTS, as an id list (.csv, .txt, .npy); Kabsch instead of ICP")
        ->excludes(pairs);
    app.add_option("--keep-fraction", icp_.keepFraction,
                   "ICP: fraction of the points kept every iteration, the closest (the expected "
                   "inlier fraction)")
        ->check(kFraction)
        ->capture_default_str();
    checkNonNegative(
        app.add_option("--median-factor", icp_.medianFactor,
                       "ICP: points farther from the surface than this times the median distance "
                       "are left out every iteration (0: none; a dozen markers: use 0, every one "
                       "of them holds the pose)"))
        ->capture_default_str();
    app.add_option("--max-iterations", icp_.maxIterations,
                   "ICP: most iterations of each refinement")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
  }

  int run() override {
    const RegistrationModel model = readRegistrationModel(model_, scale_);
    const PointsToRegister in = readPointsToRegister(points_, time_);
    if (in.fromTracks) fmt::print("frame at t = {} s of {}\n", in.time, points_);
    std::vector<int> rows;
    const Eigen::MatrixX3d points = finiteRows(in.points, &rows);
    const bool paired = !pairs_.empty() || !modelIds_.empty();

    RigidTransform transform;
    double rms = 0.0, overlap = 1.0;
    int iterations = 0, used = 0;
    std::string convergence;  // ICP only
    // The unit check's own line, unchanged; the other input errors name the points' file.
    requireMatchingUnits(points, model.surface);
    const Eigen::MatrixX3d targets =
        paired ? pairedTargets(model, in.points.rows()) : Eigen::MatrixX3d();
    try {
      if (paired) {
        Eigen::MatrixX3d P(static_cast<Eigen::Index>(rows.size()), 3), Q(P.rows(), 3);
        for (size_t k = 0; k < rows.size(); ++k) {
          P.row(static_cast<Eigen::Index>(k)) = in.points.row(rows[k]);
          Q.row(static_cast<Eigen::Index>(k)) = targets.row(rows[k]);
        }
        transform = kabschFit(P, Q);
        rms = std::sqrt((transform.apply(P) - Q).rowwise().squaredNorm().mean());
        used = static_cast<int>(P.rows());
        fmt::print("method: Kabsch on {} pairs\n", used);
      } else {
        const SurfaceRegistration r = registerPointsToSurface(points, model.surface, icp_);
        transform = r.transform;
        rms = r.rms;
        overlap = r.overlap;
        iterations = r.iterations;
        convergence = r.converged ? " (converged)"
                                  : fmt::format(
                                        " (--max-iterations reached; the last moved a point by "
                                        "{:.3g} m)",
                                        r.lastMove);
        used = static_cast<int>(std::lround(r.overlap * static_cast<double>(points.rows())));
        fmt::print(
            "method: trimmed point-to-plane ICP, {} starts probed, the best {} to convergence, "
            "start {} the deepest\n",
            icp_.startRotations.size(),
            std::min<size_t>(icp_.startRotations.size(), icp_.refinedStarts), r.start);
      }
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", points_, e.what()));
    }

    const fs::path out(out_);
    fs::create_directories(out);
    writeTransform(out, transform);
    const Eigen::MatrixX3d moved = transform.apply(points);
    const std::string movedPath = (out / "moved_points.csv").string();
    if (in.fromTracks) {
      Eigen::VectorXd marker(static_cast<Eigen::Index>(rows.size()));
      for (size_t k = 0; k < rows.size(); ++k) marker(static_cast<Eigen::Index>(k)) = rows[k];
      writePointsCsv(movedPath, moved, {{"marker", marker}});
    } else {
      writePointsCsv(movedPath, moved);
    }
    const double angle = Eigen::AngleAxisd(transform.rotation).angle() * 180.0 / std::numbers::pi;
    fmt::print("rms residual: {:.6g} m ({:.3f} mm)\n", rms, 1e3 * rms);
    fmt::print("overlap: {:.1f} % ({} of {} points)\n", 100.0 * overlap, used, points.rows());
    // A median-based limit on a few dozen points is no outlier test: 10 of 14 markers can fit a
    // pose tens of degrees off better than all 14 fit the true one.
    if (!paired && used < points.rows() && points.rows() < 50 && icp_.medianFactor > 0.0)
      fmt::print(
          "note: the trimming left {} of {} points out; markers without outliers hold the pose "
          "together: --median-factor 0 keeps them all\n",
          points.rows() - used, points.rows());
    fmt::print("iterations: {}{}\n", iterations, convergence);
    fmt::print("transform: rotation {:.3f} deg, translation {:.6g} m\n", angle,
               transform.translation.norm());
    fmt::print(
        "wrote {}/transform.csv and transform.txt (4 x 4, points' frame -> model frame, "
        "m; a scene's observations.frame_transform), {}\n",
        out.string(), movedPath);
    return 0;
  }

 private:
  // The model-frame partner of each of the n rows of POINTS.
  Eigen::MatrixX3d pairedTargets(const RegistrationModel& model, Eigen::Index n) const {
    if (!pairs_.empty()) {
      Eigen::MatrixX3d Q = readPoints(pairs_);
      if (Q.rows() != n)
        throw InputError(
            fmt::format("--pairs {}: {} points for {} rows of {}; expected one per row", pairs_,
                        Q.rows(), n, points_));
      return Q;
    }
    const std::vector<int> ids = readIndexList(modelIds_);
    if (static_cast<Eigen::Index>(ids.size()) != n)
      throw InputError(fmt::format("--model-ids {}: {} ids for {} rows of {}; expected one per row",
                                   modelIds_, ids.size(), n, points_));
    Eigen::MatrixX3d Q(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (ids[i] >= model.nodes.rows())
        throw InputError(
            fmt::format("--model-ids {}: id {} (entry {}) but {} has {} nodes; "
                        "expected ids below {}",
                        modelIds_, ids[i], i, model_, model.nodes.rows(), model.nodes.rows()));
      Q.row(i) = model.nodes.row(ids[i]);
    }
    return Q;
  }

  std::string model_, points_, out_ = "out/register", pairs_, modelIds_;
  double scale_ = 1.0;
  std::optional<double> time_;
  SurfaceRegistrationOptions icp_;
};

}  // namespace

std::unique_ptr<Command> makeTrackCommand() { return std::make_unique<TrackCommand>(); }
std::unique_ptr<Command> makeRegisterCommand() { return std::make_unique<RegisterCommand>(); }

}  // namespace bcassim
