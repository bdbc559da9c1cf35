// The thesis' human-liver experiment (§5.3) redone on a CT liver with synthetic intra-operative
// data: tackers on the truth's anterior surface seen by a camera off the model's frame (noise,
// dropouts, spurious detections, no ids), tracked, registered onto the estimation model, and the
// three scenarios of the thesis (vessels fixed only; + atlas ligament springs at their prior
// stiffness; + those springs estimated by ROUKF) compared at inner fiducials (TRE). SI units.
#pragma once
#include <string>
#include <vector>

#include "bcassim/experiments/liver/AtlasCurve.h"
#include "bcassim/experiments/liver/ErrorsOverTime.h"
#include "bcassim/experiments/liver/LiverPipeline.h"
#include "bcassim/experiments/tracked/SyntheticCamera.h"
#include "bcassim/experiments/tracked/SyntheticDepthCamera.h"
#include "bcassim/experiments/tracked/TackerRegistration.h"
#include "bcassim/experiments/tracked/TrackingScore.h"
#include "bcassim/tracking/MarkerTracker.h"

namespace bcassim {

// What the camera gives: tracked tackers (thesis §5.3), or a partial surface point cloud without
// correspondences (a depth sensor; the point-cloud variant).
enum class TrackedObservation { Tackers, Surface };

struct TrackedLiverOptions {
  // The liver experiment's values (meshes, truth, loads, time grid, spring groups, filter), with
  // markers = the number of tackers, validationPoints = the inner fiducials (thesis: 9) and
  // noise = the camera's (the standard deviation the filter assumes; the data carry their own).
  LiverScenarioOptions liver = defaultLiver();
  TrackedObservation observe = TrackedObservation::Tackers;
  CameraOptions camera;  // pose, noise and seed for both; dropouts and spurious: tackers only
  SurfaceCameraOptions surfaceCamera;  // observe = Surface
  // observe = Surface: analysis passes after the first per frame, the closest points found again
  // on the analysed surface (point_cloud.relinearizations; 0: one analysis, as the tables of
  // docs/results.md were made).
  int surfaceRelinearizations = 0;
  TrackerOptions tracker;
  // The camera sees the liver at rest for restFrames frames (t = -restFrames dt .. 0, as while
  // the tackers are placed) before the manipulation starts; the first registrationFrames frames
  // are averaged per tacker and registered (ICP); with a surface, their points together are.
  int restFrames = 10;
  int registrationFrames = 11;
  // Annotated livers (NAME.obj + NAME.eseg) for the atlas built without this liver; empty: no
  // atlas, the springs lie on the liver's own labelled curve (the phantom: one shape, no atlas).
  std::string atlasLiverDir;
  std::string atlasCacheDir;  // where the atlas is kept; empty: OUT/atlas

  static LiverScenarioOptions defaultLiver() {
    LiverScenarioOptions o;
    o.markers = 14;
    o.validationPoints = 9;
    o.noise = 0.001;
    return o;
  }
};

// TRE of one scenario at the inner fiducials against the truth.
struct ScenarioTre {
  std::string name;                      // "vessels", "prior", "estimated"
  std::vector<double> atPeakMm;          // per fiducial at the peak step
  double peakMeanMm = 0, peakMaxMm = 0;  // mean and max of those
  ErrorOverTime overTime;                // per-step mean (max) over the fiducials, over the steps
};

struct TrackedLiverReport {
  LiverScenario scenario;  // meshes, anatomy, loads (scenes: those of the liver experiment)
  int tackers = 0;
  bool surface = false;                    // observed by a point cloud (below), not tackers
  double surfaceAreaFraction = 0;          // of the truth's surface the camera sees
  int cloudPoints = 0, cloudOutliers = 0;  // over all frames
  int registeredPoints = 0;                // cloud points registered (ICP)
  bool atlasUsed = false;
  AtlasCurve atlas;
  // Distance of the springs' curve to the expert's: mean and max over the springs' curve points
  // of the distance to the expert polyline, m (0 without atlas).
  double curveDistanceMean = 0, curveDistanceMax = 0;
  // Camera and tracking.
  int detections = 0, spuriousDetections = 0;
  TrackingScore tracking;
  // The same frames tracked by the other assignment method (greedy if tracking used the optimal
  // one, and the other way round), for comparison only.
  TrackingScore otherMethod;
  std::vector<std::string> trackingProblems;  // the tracker's report, one line each
  // Registration onto the estimation model.
  SurfaceRegistration registration;  // camera -> model; rms (m), overlap, iterations
  int markers = 0;                   // tracks that became markers
  // The registration's error: the model's nodes moved by the true camera pose then by the
  // estimated inverse, against where they were (m); and the rotation left (degrees).
  double registrationErrorMean = 0, registrationErrorMax = 0, registrationAngleDegrees = 0;
  double markerOffsetMean = 0;  // markers at rest on the model vs their tackers' true rest, m
  SimulationResult truth;
  AssimilationResult assimilation;
  std::vector<ScenarioTre> scenarios;  // vessels, prior, estimated
  int peakStep = 0;                    // the truth's fiducials' largest mean displacement
  double peakDisplacementMm = 0;       // that mean displacement
  double seconds = 0;
};

// Runs everything into outDir:
//   prepare as the liver experiment (coarse.vtu, fine.vtu, curve.csv = the expert curve,
//     validation.csv = the fiducials, anatomy.csv), tackers.csv (at rest, on the truth's surface),
//     spring_curve.csv (the curve the estimation's springs come from: the atlas' or the expert's)
//   atlas/ (the left-out atlas, cached), truth/ (simulate: markers.csv are the tackers' tracks)
//   camera/detections.csv (time,x,y,z in the camera frame), camera/sources.csv (the truth of each
//     detection), camera/pose.csv (4 x 4 model -> camera)
//   track/tracks.csv (time,marker,x,y,z, camera frame), track/report.txt
//   register/transform.csv (4 x 4 camera -> model), register/markers.csv (x,y,z,track),
//     register/tracks.csv (the tracks in the model frame: the observations)
//   estimate/ (assimilate), vessels/, prior/, estimated/ (simulate: the three scenarios)
//   tre.csv (fiducial,vessels_mm,prior_mm,estimated_mm at the peak step), summary.csv
// `resume`: the truth, vessels and prior runs continue from their checkpoints (the atlas is
// always taken from its folder when complete); the rest (seconds) is redone.
// Throws InputError, NumericalError.
TrackedLiverReport runTrackedLiverPipeline(const TrackedLiverOptions& options,
                                           const std::string& outDir,
                                           const LiverCallbacks& callbacks = {},
                                           bool resume = false);

}  // namespace bcassim
