#include "bcassim/experiments/tracked/TrackedLiverPipeline.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <optional>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/experiments/liver/LiverScenes.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/Files.h"
#include "bcassim/io/PointCsvWriter.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/VisibleSurface.h"
#include "bcassim/scene/ModelParameter.h"
#include "bcassim/scene/NodePoints.h"
#include "bcassim/scene/PointCloudThinning.h"
#include "bcassim/scene/SceneBuilders.h"
#include "bcassim/tracking/LabelledTracks.h"
#include "bcassim/tracking/SurfaceRegistration.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

Eigen::MatrixX3d rowsOf(const Eigen::MatrixX3d& V, const std::vector<int>& ids) {
  Eigen::MatrixX3d P(static_cast<Eigen::Index>(ids.size()), 3);
  for (size_t i = 0; i < ids.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = V.row(ids[i]);
  return P;
}

// Tackers on the truth's anterior surface, as the liver experiment places its markers on the
// estimation mesh: boundary nodes facing anterior, away from the held vessels, spread out.
Eigen::MatrixX3d placeTackers(const TetMesh& fine, const LiverAnatomy& a, int count) {
  const BoundarySurface boundary = extractBoundary(fine);
  std::vector<int> anterior;
  for (int n : boundary.nodes) {
    const Vec3 p = fine.V.row(n).transpose();
    if (boundary.vertexNormals.row(n).dot(a.anterior) > 0.5 &&
        (p - a.hilum).norm() > 2 * a.vesselRadius)
      anterior.push_back(n);
  }
  if (static_cast<int>(anterior.size()) < count)
    throw InputError(
        fmt::format("liver: only {} anterior surface nodes of the truth for {} tackers",
                    anterior.size(), count));
  return rowsOf(fine.V, farthestPointSample(fine, anterior, count));
}

void writeMatrix4(const fs::path& path, const RigidTransform& t) {
  fs::create_directories(path.parent_path());
  std::ofstream f(path);
  for (int r = 0; r < 3; ++r)
    f << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}\n", t.rotation(r, 0), t.rotation(r, 1),
                     t.rotation(r, 2), t.translation(r));
  f << "0,0,0,1\n";
  if (!f) io::throwWriteError(path.string());
}

// The truth's tacker tracks after `restFrames` + 1 frames of the rest state (t = -restFrames dt
// .. 0): the camera records before the manipulation starts.
MarkerTracks tackerTracksFromRest(const fs::path& markersCsv, const Eigen::MatrixX3d& rest,
                                  int restFrames, double dt) {
  MarkerTracks t = readMarkerTracks(markersCsv.string());
  for (int k = 0; k <= restFrames; ++k) {
    t.times.insert(t.times.begin(), -k * dt);
    t.frames.insert(t.frames.begin(), rest);
  }
  return t;
}

// Per fiducial error of a run at one frame of validation.csv, mm.
std::vector<double> errorsAt(const fs::path& modelCsv, const MarkerTracks& truth, int frame) {
  const MarkerTracks m = readMarkerTracks(modelCsv.string());
  if (frame >= static_cast<int>(m.frames.size()) || m.numMarkers != truth.numMarkers)
    throw InputError(fmt::format("{}: expected {} fiducials over {} frames", modelCsv.string(),
                                 truth.numMarkers, truth.frames.size()));
  const Eigen::VectorXd e = (m.frames[frame] - truth.frames[frame]).rowwise().norm();
  std::vector<double> mm;
  for (Eigen::Index i = 0; i < e.size(); ++i) mm.push_back(1e3 * e(i));
  return mm;
}

void writeTrackingReport(const fs::path& path, const std::vector<std::string>& lines) {
  std::ofstream f(path);
  for (const std::string& l : lines) f << l << '\n';
  if (!f) io::throwWriteError(path.string());
}

// The camera's first guess of its pose: no rotation, the centroid of what it sees in the first
// frames on the centroid of the model's anterior surface (the side the camera is known to face).
RigidTransform firstGuess(const LiverSceneSpec& spec, const Eigen::MatrixX3d& seen) {
  const BoundarySurface boundary = extractBoundary(*spec.coarse);
  Vec3 anterior = Vec3::Zero();
  int n = 0;
  for (int node : boundary.nodes)
    if (boundary.vertexNormals.row(node).dot(spec.anatomy.anterior) > 0.5)
      anterior += spec.coarse->V.row(node).transpose(), ++n;
  RigidTransform guess;
  if (n > 0 && seen.rows() > 0)
    guess.translation = anterior / n - seen.colwise().mean().transpose();
  return guess;
}

// The registration's error against the true camera pose, over the model's nodes.
void scoreRegistration(const SurfaceRegistration& icp, const RigidTransform& modelToCamera,
                       const LiverSceneSpec& spec, TrackedLiverReport& report) {
  report.registration = icp;
  const RigidTransform roundTrip = compose(icp.transform, modelToCamera);
  const Eigen::VectorXd e = (roundTrip.apply(spec.coarse->V) - spec.coarse->V).rowwise().norm();
  report.registrationErrorMean = e.mean();
  report.registrationErrorMax = e.maxCoeff();
  report.registrationAngleDegrees =
      Eigen::AngleAxisd(roundTrip.rotation).angle() * 180.0 / std::numbers::pi;
}

struct TackerObservations {
  fs::path tracks;                 // register/tracks.csv: the tracks in the model frame
  Eigen::MatrixX3d markersAtRest;  // the markers on the model's surface
};

using StageCallback = std::function<void(const std::string&)>;

// Tackers: the camera's detections, tracked (identities), registered onto the model by ICP of
// the tracks' mean positions over the first frames.
TackerObservations observeTackers(const TrackedLiverOptions& o, const MarkerTracks& truthTackers,
                                  const Eigen::MatrixX3d& tackers, const TriMesh& modelSurface,
                                  const LiverSceneSpec& spec, const fs::path& dir,
                                  TrackedLiverReport& report, const StageCallback& stage) {
  const CameraRecording recording = recordTackers(truthTackers, o.camera);
  report.detections = recording.detections;
  report.spuriousDetections = recording.spuriousDetections;
  writeDetectionsCsv((dir / "camera" / "detections.csv").string(), recording.frames);
  writeMatrix4(dir / "camera" / "pose.csv", recording.modelToCamera);
  {
    std::ofstream f(dir / "camera" / "sources.csv");
    f << "time,detection,tacker\n";
    for (size_t k = 0; k < recording.frames.size(); ++k)
      for (size_t j = 0; j < recording.tackerOf[k].size(); ++j)
        f << fmt::format("{},{},{}\n", recording.frames[k].time, j, recording.tackerOf[k][j]);
  }

  stage("track");
  std::vector<DetectionFrame> frames;
  for (const TimedPoints& f : recording.frames) frames.push_back({f.time, f.points});
  const TrackingResult tracked = trackMarkers(frames, o.tracker);
  report.tracking = scoreTracking(tracked.ids, recording.tackerOf, report.tackers);
  report.trackingProblems = tracked.report;
  {
    TrackerOptions other = o.tracker;
    other.assignment = other.assignment == AssignmentMethod::Optimal ? AssignmentMethod::Greedy
                                                                     : AssignmentMethod::Optimal;
    report.otherMethod =
        scoreTracking(trackMarkers(frames, other).ids, recording.tackerOf, report.tackers);
  }
  const MarkerTracks cameraTracks = labelledTracks(frames, tracked);
  writeMarkerTracks((dir / "track" / "tracks.csv").string(), cameraTracks);
  writeTrackingReport(dir / "track" / "report.txt", tracked.report);

  stage("register");
  TackerRegistrationOptions ro;
  ro.frames = o.registrationFrames;
  // No trimming: tracking has removed the spurious detections, and with a dozen points on a
  // smooth surface every one of them is needed to hold the pose.
  ro.icp.medianFactor = 0.0;
  {
    std::vector<Eigen::RowVector3d> seen;
    for (size_t f = 0; f < std::min<size_t>(cameraTracks.frames.size(), o.registrationFrames); ++f)
      for (Eigen::Index k = 0; k < cameraTracks.frames[f].rows(); ++k)
        if (cameraTracks.frames[f].row(k).allFinite())
          seen.push_back(cameraTracks.frames[f].row(k));
    Eigen::MatrixX3d P(static_cast<Eigen::Index>(seen.size()), 3);
    for (size_t i = 0; i < seen.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = seen[i];
    ro.icp.initial = firstGuess(spec, P);
  }
  const TackerRegistration reg = registerTackers(cameraTracks, modelSurface, ro);
  scoreRegistration(reg.icp, recording.modelToCamera, spec, report);
  report.markers = static_cast<int>(reg.trackOfMarker.size());
  report.registeredPoints = report.markers;
  {
    int counted = 0;
    for (size_t k = 0; k < reg.trackOfMarker.size(); ++k) {
      const int tacker = report.tracking.mainTacker[reg.trackOfMarker[k]];
      if (tacker < 0) continue;
      report.markerOffsetMean +=
          (reg.markersAtRest.row(static_cast<Eigen::Index>(k)) - tackers.row(tacker)).norm();
      ++counted;
    }
    if (counted > 0) report.markerOffsetMean /= counted;
  }
  writeMatrix4(dir / "register" / "transform.csv", reg.icp.transform);
  {
    Eigen::VectorXd track(static_cast<Eigen::Index>(reg.trackOfMarker.size()));
    for (size_t k = 0; k < reg.trackOfMarker.size(); ++k)
      track(static_cast<Eigen::Index>(k)) = reg.trackOfMarker[k];
    writePointsCsv((dir / "register" / "markers.csv").string(), reg.markersAtRest,
                   {{"track", track}});
  }
  TackerObservations out{dir / "register" / "tracks.csv", reg.markersAtRest};
  writeMarkerTracks(out.tracks.string(), reg.modelTracks);
  return out;
}

// A partial surface: the depth camera's clouds, the first frames' points together registered
// onto the model by trimmed ICP, then every frame moved into the model's frame; frame k of the
// settings is the cloud at t = k dt (the rest frames before t = 0 are for the registration).
PointCloudSettings observeSurface(const TrackedLiverOptions& o, const MarkerTracks& truthSamples,
                                  const TriMesh& modelSurface, const LiverSceneSpec& spec,
                                  const fs::path& dir, TrackedLiverReport& report,
                                  const StageCallback& stage) {
  const SurfaceRecording recording = recordSurface(truthSamples, o.camera, o.surfaceCamera);
  report.cloudPoints = recording.points;
  report.cloudOutliers = recording.outliers;
  const fs::path detections = dir / "camera" / "detections.csv";
  writeDetectionsCsv(detections.string(), recording.frames);
  writeMatrix4(dir / "camera" / "pose.csv", recording.modelToCamera);

  stage("register");
  Eigen::Index count = 0;
  const size_t first = std::min<size_t>(recording.frames.size(), o.registrationFrames);
  for (size_t f = 0; f < first; ++f) count += recording.frames[f].points.rows();
  Eigen::MatrixX3d seen(count, 3);
  count = 0;
  for (size_t f = 0; f < first; ++f) {
    seen.middleRows(count, recording.frames[f].points.rows()) = recording.frames[f].points;
    count += recording.frames[f].points.rows();
  }
  SurfaceRegistrationOptions icp;  // trimmed: the outliers, and the cloud's edges off the model
  icp.initial = firstGuess(spec, seen);
  const SurfaceRegistration reg = registerPointsToSurface(seen, modelSurface, icp);
  scoreRegistration(reg, recording.modelToCamera, spec, report);
  report.registeredPoints = static_cast<int>(seen.rows());
  writeMatrix4(dir / "register" / "transform.csv", reg.transform);

  PointCloudSettings pc;
  pc.source = detections.string();
  pc.relinearizations = o.surfaceRelinearizations;
  const auto steps = static_cast<size_t>(spec.options.steps);
  pc.frames.assign(steps + 1, Eigen::MatrixX3d());
  pc.present.assign(steps + 1, false);
  pc.frameNames.assign(steps + 1, std::string());
  for (const TimedPoints& f : recording.frames) {
    const long k = std::lround(f.time / spec.options.dt);
    if (k < 0 || k > static_cast<long>(steps)) continue;
    pc.frames[static_cast<size_t>(k)] = reg.transform.apply(f.points);
    pc.present[static_cast<size_t>(k)] = true;
    pc.frameNames[static_cast<size_t>(k)] =
        fmt::format("{} at t = {:.6g} s", detections.string(), f.time);
  }
  return pc;
}

}  // namespace

TrackedLiverReport runTrackedLiverPipeline(const TrackedLiverOptions& o, const std::string& outDir,
                                           const LiverCallbacks& cb, bool resume) {
  const auto t0 = Clock::now();
  const fs::path dir(outDir);
  auto resumable = [&](const char* run) {
    return resume && fs::exists(dir / run / "checkpoint.bin");
  };
  auto stage = [&](const std::string& s) {
    if (cb.stage) cb.stage(s);
  };
  TrackedLiverReport report;

  stage("prepare");
  const LiverSceneSpec spec = prepareLiverSceneSpec(o.liver, outDir, report.scenario);
  // What the truth carries for the camera: the tackers, or the samples of the visible surface.
  report.surface = o.observe == TrackedObservation::Surface;
  Eigen::MatrixX3d carried;  // on the truth's surface, at rest
  if (report.surface) {
    const SurfaceSamples seen = sampleVisibleSurface(
        toTriMesh(*spec.fine, extractBoundary(*spec.fine)), spec.anatomy.anterior,
        o.surfaceCamera.coverage, o.surfaceCamera.samples, o.camera.seed);
    carried = seen.points;
    report.surfaceAreaFraction = seen.areaFraction;
    writePointsCsv((dir / "surface_samples.csv").string(), carried);
  } else {
    carried = placeTackers(*spec.fine, spec.anatomy, o.liver.markers);
    report.tackers = static_cast<int>(carried.rows());
    writePointsCsv((dir / "tackers.csv").string(), carried);
  }
  fs::remove(dir / "markers.csv");  // the liver experiment's markers: not this experiment's

  // The springs' curve: from the atlas built without this liver, or the liver's own.
  Eigen::MatrixX3d springCurve = spec.curve;
  if (!o.atlasLiverDir.empty()) {
    stage("atlas");
    LeftOutAtlasOptions ao;
    ao.liverDir = o.atlasLiverDir;
    ao.scale = o.liver.scale;
    ao.exclude = fs::path(o.liver.surface).stem().string();
    ao.cacheDir = o.atlasCacheDir.empty() ? (dir / "atlas").string() : o.atlasCacheDir;
    TriMesh patient = readSurface(o.liver.surface);
    patient.V *= o.liver.scale;
    report.atlas = leftOutAtlasCurve(patient, ao, cb.log);
    report.atlasUsed = true;
    springCurve = report.atlas.curve;
    const std::vector<double> d = distancesToPolyline(springCurve, spec.curve);
    for (double x : d) report.curveDistanceMean += x / static_cast<double>(d.size());
    report.curveDistanceMax = *std::max_element(d.begin(), d.end());
  }
  writePointsCsv((dir / "spring_curve.csv").string(), springCurve);

  stage("truth");
  LiverSceneSpec truthSpec = spec;
  truthSpec.markers = carried;
  report.truth = runSimulation(makeLiverTruthScene(truthSpec), (dir / "truth").string(),
                               cb.simulation, resumable("truth"));

  stage("camera");
  const MarkerTracks truthCarried =
      tackerTracksFromRest(dir / "truth" / "markers.csv", carried, o.restFrames, o.liver.dt);
  const TriMesh modelSurface = toTriMesh(*spec.coarse, extractBoundary(*spec.coarse));
  LiverSceneSpec estimationSpec = spec;
  estimationSpec.springCurve = springCurve;
  estimationSpec.ligamentNodes.clear();
  std::optional<PointCloudSettings> cloud;
  fs::path observedTracks;
  if (report.surface) {
    cloud = observeSurface(o, truthCarried, modelSurface, spec, dir, report, stage);
  } else {
    const TackerObservations seen =
        observeTackers(o, truthCarried, carried, modelSurface, spec, dir, report, stage);
    observedTracks = seen.tracks;
    estimationSpec.markers = seen.markersAtRest;
  }

  stage("estimate");
  Scene estimation = makeLiverEstimationScene(estimationSpec);
  {
    AssimilationSettings& s = estimation.assimilation.value();
    if (cloud) {
      s.observations.pointCloud = std::move(cloud);
      // As a scene's clouds are: a denser camera (--surface-points) averaged to max_points.
      thinPointCloudFrames(*s.observations.pointCloud, s.notices);
    } else {
      s.observations.tracks =
          readStepFrames(observedTracks.string(), report.markers, "tracked tackers",
                         estimation.dt(), estimation.steps, 0.0);
    }
    s.observations.noiseStddev = 0.0;  // the camera's noise is in the data already
    s.validationTruth = readStepFrames((dir / "truth" / "validation.csv").string(),
                                       static_cast<int>(estimation.validation.points.size()),
                                       "fiducials", estimation.dt(), estimation.steps, 0.0);
  }
  report.assimilation = runAssimilation(estimation, (dir / "estimate").string(), cb.assimilation);

  // The three scenarios of thesis §5.3, forward runs from rest over the whole horizon.
  stage("vessels");
  Scene vessels = makeLiverBaselineScene(estimationSpec);  // no ligament nodes: vessels only
  vessels.output.pvd = false;
  runSimulation(vessels, (dir / "vessels").string(), cb.simulation, resumable("vessels"));
  stage("prior");
  Scene prior = estimation;
  prior.assimilation.reset();
  prior.output.pvd = false;
  runSimulation(prior, (dir / "prior").string(), cb.simulation, resumable("prior"));
  stage("estimated");
  Scene estimated = estimation;
  for (size_t i = 0; i < report.assimilation.parameters.size(); ++i)
    applyParameter(estimated.assimilation->parameters[i].target,
                   report.assimilation.parameters[i].mean, estimated.model);
  estimated.assimilation.reset();
  runSimulation(estimated, (dir / "estimated").string(), cb.simulation);

  // TRE at the fiducials: at the step of the truth's largest mean fiducial displacement (the
  // thesis' deformed CT) and over the steps.
  const fs::path truthFiducials = dir / "truth" / "validation.csv";
  const MarkerTracks truth = readMarkerTracks(truthFiducials.string());
  for (size_t k = 1; k < truth.frames.size(); ++k) {
    const double d = 1e3 * (truth.frames[k] - truth.frames.front()).rowwise().norm().mean();
    if (d > report.peakDisplacementMm) {
      report.peakDisplacementMm = d;
      report.peakStep = static_cast<int>(k);
    }
  }
  for (const char* name : {"vessels", "prior", "estimated"}) {
    ScenarioTre s;
    s.name = name;
    const fs::path csv = dir / name / "validation.csv";
    s.atPeakMm = errorsAt(csv, truth, report.peakStep);
    for (double e : s.atPeakMm) s.peakMeanMm += e / static_cast<double>(s.atPeakMm.size());
    s.peakMaxMm = *std::max_element(s.atPeakMm.begin(), s.atPeakMm.end());
    s.overTime = summariseErrors(validationErrorSeries(csv.string(), truthFiducials.string()));
    report.scenarios.push_back(std::move(s));
  }
  report.seconds = secondsSince(t0);

  {
    std::ofstream f(dir / "tre.csv");
    f << "fiducial,vessels_mm,prior_mm,estimated_mm\n";
    for (size_t i = 0; i < report.scenarios[0].atPeakMm.size(); ++i)
      f << fmt::format("{},{:.6g},{:.6g},{:.6g}\n", i, report.scenarios[0].atPeakMm[i],
                       report.scenarios[1].atPeakMm[i], report.scenarios[2].atPeakMm[i]);
    if (!f) io::throwWriteError((dir / "tre.csv").string());
  }
  {
    std::ofstream f(dir / "summary.csv");
    f << "scenario,tre_peak_mean_mm,tre_peak_max_mm,tre_mean_mm,tre_mean_std_mm,tre_max_mm\n";
    for (const ScenarioTre& s : report.scenarios)
      f << fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", s.name, s.peakMeanMm, s.peakMaxMm,
                       s.overTime.meanMm, s.overTime.meanStdMm, s.overTime.maxMm);
    const TrackingScore& t = report.tracking;
    f << fmt::format("# peak step {} (t = {:.6g} s), fiducials' mean displacement {:.6g} mm\n",
                     report.peakStep, report.peakStep * o.liver.dt, report.peakDisplacementMm);
    if (report.surface)
      f << fmt::format(
          "# surface camera: {:.6g} of the area seen, {} samples, {} points per frame, {} "
          "outliers of {} points\n",
          report.surfaceAreaFraction, o.surfaceCamera.samples, o.surfaceCamera.pointsPerFrame,
          report.cloudOutliers, report.cloudPoints);
    else
      f << fmt::format(
          "# tracking: {} tackers, {} tracks, {} switches, {} wrong labels, {} of {} spurious "
          "labelled, {} tacker detections unlabelled; the other method: {} tracks, {} switches, "
          "{} wrong labels\n",
          report.tackers, t.tracks, t.identitySwitches, t.wrongLabels, t.spuriousLabelled,
          report.spuriousDetections, t.unlabelled, report.otherMethod.tracks,
          report.otherMethod.identitySwitches, report.otherMethod.wrongLabels);
    f << fmt::format(
        "# registration: rms {:.6g} mm, overlap {:.6g}, {} iterations ({}), error mean {:.6g} mm "
        "max {:.6g} mm, "
        "{:.6g} deg; markers {:.6g} mm off their tackers; {} points registered\n"
        "# springs' curve to the expert's: mean {:.6g} mm, max {:.6g} mm{}\n"
        "# assimilation median step {:.6g} ms; atlas build {:.6g} s, transfer {:.6g} s; truth "
        "{:.6g} s; total {:.6g} s\n",
        1e3 * report.registration.rms, report.registration.overlap, report.registration.iterations,
        report.registration.converged ? "converged"
                                      : fmt::format("not converged, the last moved {:.3g} mm",
                                                    1e3 * report.registration.lastMove),
        1e3 * report.registrationErrorMean, 1e3 * report.registrationErrorMax,
        report.registrationAngleDegrees, 1e3 * report.markerOffsetMean, report.registeredPoints,
        1e3 * report.curveDistanceMean, 1e3 * report.curveDistanceMax,
        report.atlasUsed ? "" : " (no atlas: the expert curve)", report.assimilation.medianStepMs,
        report.atlas.buildSeconds, report.atlas.transferSeconds, report.truth.wallSeconds,
        report.seconds);
    if (!f) io::throwWriteError((dir / "summary.csv").string());
  }
  return report;
}

}  // namespace bcassim
