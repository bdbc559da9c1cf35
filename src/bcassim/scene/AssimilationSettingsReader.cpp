#include "bcassim/scene/AssimilationSettingsReader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "bcassim/Error.h"
#include "bcassim/io/IndexListReader.h"
#include "bcassim/io/NpyReader.h"
#include "bcassim/io/PointCloudFrames.h"
#include "bcassim/io/RigidTransformReader.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/scene/PointCloudThinning.h"
#include "bcassim/scene/SceneBuilders.h"

namespace bcassim {

TrackFrames toStepFrames(const MarkerTracks& tracks, const std::string& file, int numPoints,
                         const std::string& pointsName, double dt, int steps, double timeOffset) {
  if (tracks.numMarkers != numPoints)
    throw InputError(
        fmt::format("'{}' holds {} points (1 + largest marker index); the scene has {} {}", file,
                    tracks.numMarkers, numPoints, pointsName));
  TrackFrames out;
  out.file = file;
  out.frames.assign(steps + 1, Eigen::MatrixX3d::Constant(
                                   numPoints, 3, std::numeric_limits<double>::quiet_NaN()));
  out.present.assign(steps + 1, false);
  for (size_t f = 0; f < tracks.times.size(); ++f) {
    const double s = (tracks.times[f] - timeOffset) / dt;
    const double k = std::round(s);
    // Times are written with full precision, so anything beyond rounding noise is another dt.
    if (std::abs(s - k) > 1e-3)
      throw InputError(fmt::format(
          "'{}': frame at time {:.9g} s is not on the scene's time grid {:.9g} s + k x {:.9g} s "
          "(time.dt); the tracks must come from a run with the same dt",
          file, tracks.times[f], timeOffset, dt));
    if (k < 0 || k > steps) continue;
    out.frames[static_cast<size_t>(k)] = tracks.frames[f];
    out.present[static_cast<size_t>(k)] = true;
  }
  return out;
}

namespace yamlio {

namespace {

const std::vector<std::string> kAssimilationKeys = {"filter",
                                                    "sigma_points",
                                                    "sigma_spread",
                                                    "members",
                                                    "inflation",
                                                    "seed",
                                                    "threads",
                                                    "forecast_retries",
                                                    "reforecasts",
                                                    "reforecast_beyond",
                                                    "state",
                                                    "reuse_factorization",
                                                    "tangent",
                                                    "tangent_refresh_every",
                                                    "tangent_background",
                                                    "tangent_background_steps",
                                                    "tangent_precision",
                                                    "parameters",
                                                    "observations",
                                                    "validation"};

std::string indexed(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// Young's modulus target: model and Poisson's ratio default to the region's scene material.
YoungModulusTarget readYoungTarget(const YamlSource& src, const MapReader& r,
                                   const MechanicalModel& model) {
  YoungModulusTarget t;
  t.region = r.integer("region", 0);
  const int regions = model.elasticity.numRegions();
  if (t.region >= regions)
    r.fail("region",
           fmt::format("expected a material region in [0, {}), got {}", regions, t.region));
  const Material& material = model.elasticity.material(t.region);
  t.model = r.choice("model", materialName(material),
                     {"linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"});
  const double nu = std::visit(
      [](const auto& m) -> double {
        if constexpr (requires {
                        m.lambda;
                        m.mu;
                      })
          return m.lambda / (2 * (m.lambda + m.mu));
        else
          return std::numeric_limits<double>::quiet_NaN();
      },
      material);
  if (std::isnan(nu) && !r.has("poisson_ratio"))
    failAt(src, r.self(), r.pathOf("poisson_ratio"),
           "missing (the region's material does not give one)");
  t.poissonRatio = r.number("poisson_ratio", nu, "-");
  if (!(t.poissonRatio > -1.0 && t.poissonRatio < 0.5))
    r.fail("poisson_ratio", "must be in (-1, 0.5), got " + r.node("poisson_ratio").Scalar());
  return t;
}

SpringCoefficientTarget readSpringTarget(const MapReader& r, const MechanicalModel& model) {
  SpringCoefficientTarget t;
  t.group = r.integer("group", 0);
  const int groups = model.springs.numGroups();
  if (t.group >= groups)
    r.fail("group", groups == 0 ? std::string("the scene has no springs")
                                : fmt::format("expected a spring group in [0, {}), got {}", groups,
                                              t.group));
  const std::string c = r.choice("coefficient", "alpha", {"alpha", "beta", "gamma"});
  t.coefficient = c == "alpha" ? 0 : c == "beta" ? 1 : 2;
  return t;
}

EstimatedParameter readParameter(const YamlSource& src, const YAML::Node& node,
                                 const std::string& path, const MechanicalModel& model, double dt) {
  MapReader r(src, node, path,
              {"name", "young_modulus", "spring", "force", "pose", "mean", "stddev", "transform",
               "lower", "upper", "truth", "random_walk", "random_walk_per_step"});
  const int targets = (r.has("young_modulus") ? 1 : 0) + (r.has("spring") ? 1 : 0) +
                      (r.has("force") ? 1 : 0) + (r.has("pose") ? 1 : 0);
  if (targets != 1)
    failAt(src, node, path,
           "expected exactly one of young_modulus, spring, force, pose (what it sets)");
  EstimatedParameter p;
  std::string unit;
  if (r.has("pose")) {
    const std::string c = r.choice("pose", "rx", {"rx", "ry", "rz", "tx", "ty", "tz"});
    const int component = (c[0] == 't' ? 3 : 0) + (c[1] - 'x');
    p.target = ObservationPoseTarget{component};
    unit = component < 3 ? "rad" : "m";
  } else if (r.has("force")) {
    MapReader t(src, r.node("force"), r.pathOf("force"), {"load", "component", "footprint"});
    LoadForceTarget target;
    target.load = t.integer("load", 0);
    const int loads = static_cast<int>(model.loads.size());
    if (target.load >= loads)
      t.fail("load", loads == 0
                         ? std::string("the scene has no loads (the zone the force acts on)")
                         : fmt::format("expected a load in [0, {}), got {}", loads, target.load));
    if (!model.loads[static_cast<size_t>(target.load)].frames.empty())
      t.fail("load", fmt::format("loads[{}] is given frame by frame (total_force_frames); an "
                                 "estimated force needs a constant one",
                                 target.load));
    if (t.has("footprint")) {
      if (t.has("component"))
        t.fail("footprint", "expected either component or footprint, not both");
      const std::string which =
          t.choice("footprint", "tilt_u", {"tilt_u", "tilt_v", "concentration"});
      const int nodes =
          static_cast<int>(model.loads[static_cast<size_t>(target.load)].nodes.size());
      if (nodes < 3)
        t.fail("footprint", fmt::format("loads[{}] has {} node{}; a footprint needs at least 3",
                                        target.load, nodes, nodes == 1 ? "" : "s"));
      p.target = LoadFootprintTarget{target.load, which == "tilt_u"   ? 0
                                                  : which == "tilt_v" ? 1
                                                                      : 2};
      unit = "-";
    } else {
      if (!t.has("component")) failAt(src, t.self(), t.pathOf("component"), "missing (x, y or z)");
      target.component = t.choice("component", "x", {"x", "y", "z"})[0] - 'x';
      p.target = target;
      unit = "N";
    }
  } else if (r.has("young_modulus")) {
    MapReader t(src, r.node("young_modulus"), r.pathOf("young_modulus"),
                {"region", "model", "poisson_ratio"});
    p.target = readYoungTarget(src, t, model);
    unit = "Pa";
  } else {
    MapReader t(src, r.node("spring"), r.pathOf("spring"), {"group", "coefficient"});
    const SpringCoefficientTarget target = readSpringTarget(t, model);
    p.target = target;
    const char* units[] = {"N/m^3", "N/m^2", "N/m"};
    unit = units[target.coefficient];
  }
  p.name = r.text("name", defaultParameterName(p.target));
  if (p.name.empty() || p.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTU"
                                                 "VWXYZ0123456789_-.") != std::string::npos)
    r.fail("name",
           "expected a name of letters, digits, '_', '-', '.', got " + describe(r.node("name")));
  if (!r.has("mean")) failAt(src, node, r.pathOf("mean"), "missing (initial value, " + unit + ")");
  if (!r.has("stddev"))
    failAt(src, node, r.pathOf("stddev"), "missing (initial standard deviation, " + unit + ")");
  p.mean = r.number("mean", 0.0, unit);
  p.stddev = r.number("stddev", 0.0, unit, Range::Positive);
  const std::string kind =
      r.choice("transform", "none", {"none", "abs", "log", "exp", "projection", "bounded-log"});
  const bool box = kind == "projection" || kind == "bounded-log";
  r.rejectUnless(box, "lower", "transform projection or bounded-log");
  r.rejectUnless(box, "upper", "transform projection or bounded-log");
  if (box) {
    if (!r.has("lower") || !r.has("upper"))
      failAt(src, node, path, "transform " + kind + " needs lower and upper");
    const double lo =
        r.number("lower", 0.0, unit, kind == "bounded-log" ? Range::Positive : Range::Any);
    const double hi = r.number("upper", 0.0, unit);
    if (!(lo < hi)) r.fail("upper", fmt::format("must be > lower ({:.6g}), got {:.6g}", lo, hi));
    p.transform = kind == "projection" ? ParameterTransform::projection(lo, hi)
                                       : ParameterTransform::boundedLog(lo, hi);
  } else {
    p.transform = kind == "none"  ? ParameterTransform::identity()
                  : kind == "abs" ? ParameterTransform::absolute()
                                  : ParameterTransform::exponential();
  }
  try {
    p.transform.toUnconstrained(p.mean);
  } catch (const InputError&) {
    r.fail("mean", fmt::format("{:.6g} is outside the range of transform {}", p.mean, kind));
  }
  if (r.has("truth")) p.truth = r.number("truth", 0.0, unit);
  if (r.has("random_walk") && r.has("random_walk_per_step"))
    r.fail("random_walk_per_step", "expected either random_walk or random_walk_per_step, not both");
  // A random walk of standard deviation w per sqrt(s) moves a parameter by w sqrt(dt) per step.
  p.randomWalkPerStep =
      r.has("random_walk_per_step")
          ? r.number("random_walk_per_step", 0.0, unit, Range::NonNegative)
          : r.number("random_walk", 0.0, unit + "/s^0.5", Range::NonNegative) * std::sqrt(dt);
  return p;
}

TrackFrames readFrames(const YamlSource& src, const MapReader& r, const std::string& key,
                       int numPoints, const std::string& pointsName, const AssimilationContext& c,
                       double offset) {
  const std::string file = r.existingFile(key);
  TrackFrames frames;
  withContext(src, r.node(key), r.pathOf(key),
              [&] { frames = readStepFrames(file, numPoints, pointsName, c.dt, c.steps, offset); });
  return frames;
}

// Triangles (node ids, one row each) from .npy ((F, 3) integers) or a .txt/.csv id list read
// three at a time.
Eigen::MatrixX3i readTriangles(const std::string& path, Eigen::Index nodes) {
  std::vector<std::int64_t> ids;
  if (std::filesystem::path(path).extension() == ".npy") {
    const NpyArray a = readNpy(path);
    if (a.shape.size() != 2 || a.shape[1] != 3 || a.shape[0] < 1)
      throw InputError(fmt::format("{}: array of shape {}; expected (F, 3) node ids", path,
                                   formatNpyShape(a.shape)));
    for (double v : a.values) {
      if (v != std::floor(v))
        throw InputError(fmt::format("{}: {} is not a node id (an integer)", path, v));
      ids.push_back(static_cast<std::int64_t>(v));
    }
  } else {
    for (int id : readIndexList(path)) ids.push_back(id);
    if (ids.size() % 3 != 0)
      throw InputError(fmt::format("{}: {} ids; expected 3 per triangle", path, ids.size()));
  }
  Eigen::MatrixX3i F(static_cast<Eigen::Index>(ids.size() / 3), 3);
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] < 0 || ids[i] >= nodes)
      throw InputError(fmt::format("{}: triangle {} names node {}; the mesh has {} nodes", path,
                                   i / 3, ids[i], nodes));
    F(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) =
        static_cast<int>(ids[i]);
  }
  return F;
}

// point_cloud.max_points' floor: a voxel grid coarser than the whole cloud still leaves 8 cells.
constexpr int kSmallestMaxPoints = 8;

// observations.point_cloud: the frames on the scene's steps (thinned as voxel_size and max_points
// say), the observed surface and the robust threshold. Frames a step cannot use become notices,
// not errors.
PointCloudSettings readPointCloud(const YamlSource& src, const MapReader& obs,
                                  const AssimilationContext& c, double timeOffset,
                                  const std::optional<RigidTransform>& toModel,
                                  std::vector<std::string>& notices) {
  MapReader r(src, obs.node("point_cloud"), obs.pathOf("point_cloud"),
              {"files", "csv", "first_step", "surface", "residual", "distance_factor",
               "min_distance", "max_distance", "keep_fraction", "min_points", "relinearizations",
               "voxel_size", "max_points"});
  if (r.has("files") == r.has("csv"))
    failAt(src, r.self(), r.pathOf("files"),
           r.has("files") ? "expected either files or csv, not both"
                          : "missing (a folder or pattern of frame files, or a csv)");
  PointCloudSettings pc;
  pc.residual = r.choice("residual", "normal", {"normal", "point"}) == "normal"
                    ? CloudResidual::Normal
                    : CloudResidual::Point;
  pc.distanceFactor = r.number("distance_factor", pc.distanceFactor, "-", Range::Positive);
  pc.minCutoff = r.number("min_distance", pc.minCutoff, "m", Range::NonNegative);
  pc.maxCutoff = r.number("max_distance", pc.maxCutoff, "m", Range::Positive, true);
  if (pc.maxCutoff < pc.minCutoff)
    r.fail("max_distance", fmt::format("{:.6g} m is below min_distance ({:.6g} m); expected at "
                                       "least that",
                                       pc.maxCutoff, pc.minCutoff));
  pc.keepFraction = r.number("keep_fraction", pc.keepFraction, "-", Range::Positive);
  if (pc.keepFraction > 1.0)
    r.fail("keep_fraction",
           fmt::format("{:.6g}; expected a fraction in (0, 1] of each frame's points",
                       pc.keepFraction));
  pc.minPoints = r.integer("min_points", pc.minPoints, Range::AtLeastOne);
  pc.relinearizations = r.integer("relinearizations", pc.relinearizations, Range::NonNegative);
  pc.voxelSize = r.number("voxel_size", pc.voxelSize, "m", Range::NonNegative);
  if (pc.voxelSize > 0 && (pc.voxelSize < 1e-6 || pc.voxelSize > 1.0))
    r.fail("voxel_size",
           fmt::format("{:.6g} m; expected 0 (none) or an edge from 1e-6 to 1 m", pc.voxelSize));
  pc.maxPoints = r.integer("max_points", pc.maxPoints, Range::AtLeastOne);
  if (pc.maxPoints < std::max(pc.minPoints, kSmallestMaxPoints))
    r.fail("max_points", fmt::format("{}; expected at least {} (and at least min_points, {})",
                                     pc.maxPoints, kSmallestMaxPoints, pc.minPoints));
  const int firstStep = r.integer("first_step", 1);
  const auto steps = static_cast<size_t>(c.steps);
  pc.frames.assign(steps + 1, Eigen::MatrixX3d());
  pc.present.assign(steps + 1, false);
  pc.frameNames.assign(steps + 1, "");
  // Frames beyond the horizon are ignored, as track frames are; a second one for a step too.
  auto place = [&](long step, CloudFrame frame) {
    if (step < 1 || step > c.steps) return;
    const auto k = static_cast<size_t>(step);
    if (pc.present[k]) {
      notices.push_back(fmt::format("{}: a second frame for step {} (after {}); ignored",
                                    frame.name, step, pc.frameNames[k]));
      return;
    }
    pc.frames[k] = std::move(frame.points);
    pc.frameNames[k] = std::move(frame.name);
    pc.present[k] = true;
  };
  if (r.has("files")) {
    pc.source = resolvePath(src.directory, r.text("files", ""));
    std::vector<std::string> files;
    withContext(src, r.node("files"), r.pathOf("files"),
                [&] { files = cloudFrameFiles(pc.source); });
    for (size_t i = 0; i < files.size(); ++i) {
      CloudFrame frame;
      withContext(src, r.node("files"), r.pathOf("files"),
                  [&] { frame.points = readCloudFile(files[i], notices); });
      frame.name = std::filesystem::path(files[i]).filename().string();
      place(firstStep + static_cast<long>(i), std::move(frame));
    }
  } else {
    pc.source = r.existingFile("csv");
    bool byTime = false;
    std::vector<CloudFrame> frames;
    withContext(src, r.node("csv"), r.pathOf("csv"),
                [&] { frames = readCloudCsv(pc.source, byTime, notices); });
    if (byTime) r.rejectUnless(false, "first_step", "frames numbered by a frame column");
    for (CloudFrame& frame : frames) {
      long step = firstStep + static_cast<long>(frame.key);
      if (byTime) {
        // As for tracks: times are on the scene's grid up to rounding noise.
        const double at = (frame.key - timeOffset) / c.dt;
        step = std::lround(at);
        if (std::abs(at - static_cast<double>(step)) > 1e-3)
          r.fail("csv", fmt::format("{} is not on the scene's time grid {:.9g} s + k x {:.9g} s "
                                    "(time.dt)",
                                    frame.name, timeOffset, c.dt));
      }
      place(step, std::move(frame));
    }
  }
  // Into the model's frame before the voxel grids, which are anchored at its origin.
  if (toModel)
    for (size_t k = 0; k < pc.frames.size(); ++k)
      if (pc.present[k] && pc.frames[k].rows() > 0) pc.frames[k] = toModel->apply(pc.frames[k]);
  thinPointCloudFrames(pc, notices);
  int usable = 0;
  for (size_t k = 1; k <= steps; ++k) {
    if (!pc.present[k]) continue;
    const Eigen::Index n = pc.frames[k].rows();
    if (n < pc.minPoints) {
      notices.push_back(
          n == 0 ? fmt::format("{}: no point; step {} is a prediction only", pc.frameNames[k], k)
                 : fmt::format("{}: {} point{}, fewer than point_cloud.min_points ({}); step {} is "
                               "a prediction only",
                               pc.frameNames[k], n, n == 1 ? "" : "s", pc.minPoints, k));
      pc.present[k] = false;
      continue;
    }
    ++usable;
  }
  if (usable == 0)
    failAt(src, r.self(), obs.pathOf("point_cloud"),
           fmt::format("no frame with at least min_points ({}) points within time.steps ({})",
                       pc.minPoints, c.steps));
  if (r.has("surface")) {
    const std::string file = r.existingFile("surface");
    withContext(src, r.node("surface"), r.pathOf("surface"),
                [&] { pc.surface = readTriangles(file, c.model.mesh->numNodes()); });
  }
  return pc;
}

}  // namespace

bool sharesSolverFactorization(const YamlSource& src, const YAML::Node& node) {
  const MapReader r(src, node, "assimilation", kAssimilationKeys);
  return r.boolean("reuse_factorization", true) &&
         r.choice("tangent", "own", {"own", "mean"}) == "own";
}

AssimilationSettings readAssimilationSettings(const YamlSource& src, const YAML::Node& node,
                                              const AssimilationContext& c) {
  MapReader r(src, node, "assimilation", kAssimilationKeys);
  AssimilationSettings s;
  const std::string filter = r.choice("filter", "roukf", {"ukf", "roukf", "etkf"});
  s.filter = filter == "ukf"     ? FilterKind::Ukf
             : filter == "roukf" ? FilterKind::Roukf
                                 : FilterKind::Etkf;
  r.rejectUnless(s.filter != FilterKind::Etkf, "sigma_points", "filters ukf and roukf");
  r.rejectUnless(s.filter == FilterKind::Etkf, "members", "filter etkf");
  // A parameter's random walk is the way to process noise with roukf (in its reduced space).
  r.rejectUnless(s.filter != FilterKind::Roukf, "inflation",
                 "filters ukf and etkf (roukf keeps its rank)");
  const std::string sigma =
      r.choice("sigma_points", s.filter == FilterKind::Ukf ? "star" : "simplex",
               {"star", "canonical", "simplex"});
  s.sigmaPoints = sigma == "star"        ? SigmaPointKind::Star
                  : sigma == "canonical" ? SigmaPointKind::Canonical
                                         : SigmaPointKind::Simplex;
  r.rejectUnless(s.filter == FilterKind::Ukf, "sigma_spread", "filter ukf");
  s.sigmaSpread = r.number("sigma_spread", 1.0, "-", Range::Positive);
  s.members = r.integer("members", 6);
  if (s.members < 2) r.fail("members", "must be >= 2, got " + std::to_string(s.members));
  s.inflation = r.number("inflation", 0.0, "-", Range::NonNegative);
  s.seed = static_cast<std::uint64_t>(r.integer("seed", 1));
  s.threads = r.integer("threads", 1, Range::AtLeastOne);
  s.forecastRetries = r.integer("forecast_retries", s.forecastRetries, Range::NonNegative);
  if (s.forecastRetries > 20)
    r.fail("forecast_retries", "must be <= 20 (the sigma points at 1/2^20 of their spread), got " +
                                   std::to_string(s.forecastRetries));
  s.reforecasts = r.integer("reforecasts", 0, Range::NonNegative);
  if (s.reforecasts > 20)
    r.fail("reforecasts", "must be <= 20, got " + std::to_string(s.reforecasts));
  if (s.reforecasts > 0 && s.filter != FilterKind::Roukf)
    r.fail("reforecasts", "needs filter: roukf, got " + filter);
  if (s.reforecasts > 0 && !c.statics)
    r.fail("reforecasts",
           "needs integrator.type static (a dynamic step has no equilibrium to re-centre on)");
  r.rejectUnless(s.reforecasts > 0, "reforecast_beyond", "reforecasts > 0");
  s.reforecastBeyond = r.number("reforecast_beyond", 1.0, "-", Range::Positive);
  MapReader state(src, r.node("state"), r.pathOf("state"), {"positions", "velocities"});
  // A static frame is a function of the parameters alone: nothing mechanical to carry.
  s.carryPositions = state.boolean("positions", !c.statics);
  s.carryVelocities = state.boolean("velocities", !c.statics);
  for (const char* key : {"positions", "velocities"})
    if (c.statics && state.boolean(key, false))
      state.fail(key,
                 "true does not go with integrator.type static (every frame is an "
                 "equilibrium of the parameters: the filter estimates parameters only)");
  s.reuseFactorization = r.boolean("reuse_factorization", true);
  s.meanTangent = r.choice("tangent", "own", {"own", "mean"}) == "mean";
  if (s.meanTangent &&
      c.model.springs.springs().size() > static_cast<size_t>(FrozenTangent::kMaxCorrectedSprings))
    r.fail("tangent",
           fmt::format("mean corrects at most {} springs exactly (the springs' stiffness is each "
                       "sigma point's own); this scene has {}: use tangent: own",
                       FrozenTangent::kMaxCorrectedSprings, c.model.springs.springs().size()));
  s.tangentRefreshEvery = r.integer("tangent_refresh_every", 1, Range::AtLeastOne);
  s.tangentInBackground = r.boolean("tangent_background", false);
  s.tangentBackgroundSteps = r.integer("tangent_background_steps", 0, Range::AtLeastOne);
  s.tangentSinglePrecision =
      r.choice("tangent_precision", "double", {"double", "single"}) == "single";
  r.rejectUnless(s.meanTangent, "tangent_refresh_every", "tangent: mean");
  r.rejectUnless(s.meanTangent, "tangent_background", "tangent: mean");
  r.rejectUnless(s.tangentInBackground, "tangent_background_steps", "tangent_background: true");
  if (s.tangentBackgroundSteps > s.tangentRefreshEvery)
    r.fail("tangent_background_steps",
           fmt::format("{} is more than tangent_refresh_every ({}): a build is adopted at the "
                       "latest when the next one is due",
                       s.tangentBackgroundSteps, s.tangentRefreshEvery));
  r.rejectUnless(s.meanTangent, "tangent_precision", "tangent: mean");
  r.rejectUnless(!c.statics, "tangent_precision",
                 "dynamic frames (static ones solve their chord steps in float already)");
  if (s.meanTangent && !s.reuseFactorization)
    r.fail("reuse_factorization",
           "false does not go with tangent: mean (every sigma point steps with the mean's one "
           "factorisation)");
  if (s.reuseFactorization && !s.meanTangent && c.solverType != "factorized-pcg") {
    const std::string what = "needs solver.type factorized-pcg, got " + c.solverType;
    if (r.has("reuse_factorization")) r.fail("reuse_factorization", what);
    failAt(src, node, r.pathOf("reuse_factorization"),
           what + " (true by default; false solves every sigma point with " + c.solverType + ")");
  }

  const auto entries = listElements(src, r.node("parameters"), r.pathOf("parameters"));
  if (entries.empty())
    failAt(src, r.has("parameters") ? r.node("parameters") : node, r.pathOf("parameters"),
           "expected a non-empty list of estimated parameters");
  std::set<std::string> names;
  std::set<int> poses;
  for (size_t i = 0; i < entries.size(); ++i) {
    const std::string path = indexed(r.pathOf("parameters"), i);
    s.parameters.push_back(readParameter(src, entries[i], path, c.model, c.dt));
    if (!names.insert(s.parameters.back().name).second)
      failAt(src, entries[i], path + ".name",
             "name '" + s.parameters.back().name + "' is used twice");
    if (const auto* pose = std::get_if<ObservationPoseTarget>(&s.parameters.back().target);
        pose && !poses.insert(pose->component).second)
      failAt(src, entries[i], path + ".pose",
             fmt::format("{} is estimated twice; expected each pose coordinate once",
                         defaultParameterName(*pose)));
  }

  if (!r.has("observations"))
    failAt(src, node, r.pathOf("observations"),
           "missing (tracks of the observed markers, or a point_cloud)");
  MapReader obs(src, r.node("observations"), r.pathOf("observations"),
                {"tracks", "point_cloud", "noise_stddev", "sigma", "adaptive_noise", "until_step",
                 "time_offset", "model_error", "frame_transform"});
  if (obs.has("tracks") == obs.has("point_cloud"))
    failAt(src, obs.self(), obs.pathOf("tracks"),
           obs.has("tracks") ? "expected either tracks or point_cloud, not both"
                             : "missing (CSV time,marker,x,y,z in s and m, or a point_cloud)");
  s.observations.timeOffset = obs.number("time_offset", 0.0, "s");
  s.observations.noiseStddev = obs.number("noise_stddev", 0.0, "m", Range::NonNegative);
  s.observations.sigma = obs.number("sigma", 1e-4, "m", Range::Positive);
  if (obs.has("adaptive_noise")) {
    const MapReader a(src, obs.node("adaptive_noise"), obs.pathOf("adaptive_noise"),
                      {"window", "floor"});
    AdaptiveNoiseSettings n;
    n.window = a.integer("window", n.window, Range::AtLeastOne);
    n.floor = a.number("floor", n.floor, "m", Range::Positive);
    if (n.floor > s.observations.sigma)
      a.fail("floor", fmt::format("must be <= observations.sigma ({:g} metres), got {}",
                                  s.observations.sigma,
                                  a.has("floor") ? a.node("floor").Scalar()
                                                 : fmt::format("{:g} (the default)", n.floor)));
    s.observations.adaptiveNoise = n;
  }
  s.observations.untilStep = obs.integer("until_step", c.steps);
  s.observations.modelErrorGrows =
      obs.choice("model_error", "grows", {"grows", "constant"}) == "grows";
  if (obs.has("frame_transform")) {
    const std::string file = obs.existingFile("frame_transform");
    withContext(src, obs.node("frame_transform"), obs.pathOf("frame_transform"),
                [&] { s.observations.frameTransform = readRigidTransform(file); });
  }
  if (obs.has("tracks")) {
    if (c.markers == 0)
      obs.fail("tracks", "the scene has no markers; add a markers: section (the observed points)");
    if (obs.text("tracks", "") == "stream") {
      // bcassim serve: the markers come from OpenIGTLink, frame by frame; no file.
      s.observations.streamed = true;
      s.observations.tracks.file = "stream";
      s.observations.tracks.frames.assign(
          static_cast<size_t>(c.steps) + 1,
          Eigen::MatrixX3d::Constant(c.markers, 3, std::numeric_limits<double>::quiet_NaN()));
      s.observations.tracks.present.assign(static_cast<size_t>(c.steps) + 1, false);
    } else {
      s.observations.tracks =
          readFrames(src, obs, "tracks", c.markers, "markers", c, s.observations.timeOffset);
      if (s.observations.frameTransform)
        for (Eigen::MatrixX3d& frame : s.observations.tracks.frames)
          frame = s.observations.frameTransform->apply(frame);  // NaN rows (not seen) stay NaN
    }
  } else {
    s.observations.pointCloud = readPointCloud(src, obs, c, s.observations.timeOffset,
                                               s.observations.frameTransform, s.notices);
  }

  MapReader val(src, r.node("validation"), r.pathOf("validation"), {"tracks"});
  if (val.has("tracks")) {
    if (c.validationPoints == 0)
      val.fail("tracks", "the scene has no validation_points (the points the tracks follow)");
    s.validationTruth = readFrames(src, val, "tracks", c.validationPoints, "validation points", c,
                                   s.observations.timeOffset);
  }
  return s;
}

}  // namespace yamlio
}  // namespace bcassim
