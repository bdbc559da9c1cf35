// The `assimilation:` section of a scene (docs/assimilation-format.md): which filter estimates
// which model parameters from which observed tracks, and what truth the result is validated on.
#pragma once
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bcassim/assimilation/ParameterTransform.h"
#include "bcassim/assimilation/SigmaPointSet.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/scene/ModelParameter.h"

namespace bcassim {

enum class FilterKind { Ukf, Roukf, Etkf };

// One estimated scalar and what it sets in the model.
struct EstimatedParameter {
  std::string name;  // as written in estimates.csv
  ModelParameterTarget target;
  double mean = 0.0;    // initial physical value (Pa, N/m^3, N/m^2, N/m)
  double stddev = 0.0;  // initial physical standard deviation, same unit
  ParameterTransform transform;
  std::optional<double> truth;  // known true value, for reports and plots only
  // Random walk: standard deviation of the change per step, physical unit (random_walk x
  // sqrt(dt), or random_walk_per_step); 0 = a constant parameter.
  double randomWalkPerStep = 0.0;
};

// Positions on the scene's time grid: frame k holds the positions at time timeOffset + k dt,
// NaN rows for points not seen. Frames absent from the file are NaN throughout.
struct TrackFrames {
  std::string file;                      // as resolved, for messages
  std::vector<Eigen::MatrixX3d> frames;  // index k = 0 .. steps; k = 0 is the rest state
  std::vector<bool> present;             // frame k was in the file
};

// How a cloud point's distance to the model's surface is measured (observed).
enum class CloudResidual {
  Normal,  // along the surface normal at its closest point: one entry per point (point-to-plane)
  Point,   // the closest point itself, three entries per point (point-to-point)
};

// A partial surface seen as unlabelled points, frame by frame (observations.point_cloud): each
// point observes its closest point on the model's surface, found again every step at the forecast
// mean; points farther than max(distanceFactor x median distance, minCutoff) are dropped for
// that step.
struct PointCloudSettings {
  std::string source;                    // folder, pattern or CSV as resolved, for messages
  std::vector<Eigen::MatrixX3d> frames;  // index k = 0 .. steps: the points of step k, m
  std::vector<bool> present;             // step k has a frame
  std::vector<std::string> frameNames;   // "pc07.txt", "cloud.csv frame 7": for notices
  // Observed part of the surface: triangles by node ids (counter-clockwise from outside not
  // needed); empty = the whole boundary surface of the mesh.
  Eigen::MatrixX3i surface;
  CloudResidual residual = CloudResidual::Normal;
  double distanceFactor = 3.0;  // -, k of the robust threshold
  double minCutoff = 0.005;     // m, the threshold's floor
  // m, the threshold's ceiling (infinity: none): what lies farther is never the organ (a table,
  // an instrument in view).
  double maxCutoff = std::numeric_limits<double>::infinity();
  // Only the closest keepFraction of each frame's points count (0 < f <= 1: the expected share
  // of organ points in the frame), the median and the threshold taken among them: a background
  // covering half the view or more would otherwise move the median and keep itself in.
  double keepFraction = 1.0;
  int minPoints = 10;  // a frame with fewer usable points is not used (prediction only)
  // Each frame averaged on a voxel grid of this edge (m; 0: not), then, where it still has more
  // than maxPoints, on coarser grids until it has no more (mesh/VoxelGrid): a dense RGB-D frame
  // costs what a few thousand points cost.
  double voxelSize = 0.0;
  int maxPoints = 2000;
  // Analysis passes after the first that find the closest points again on the analysed surface
  // and correct from the same forecasts (FilterOptions::relinearizations; ROUKF, UKF, ETKF).
  int relinearizations = 0;
};

// observations.adaptive_noise: sigma estimated from the innovations (InnovationNoiseEstimator),
// starting from observations.sigma.
struct AdaptiveNoiseSettings {
  int window = 30;      // observed steps the estimate is made over
  double floor = 1e-6;  // m, the smallest sigma (<= observations.sigma)
};

struct ObservationSettings {
  TrackFrames tracks;  // observed marker positions, m (empty with a point cloud)
  std::optional<PointCloudSettings> pointCloud;  // instead of marker tracks
  double noiseStddev = 0.0;  // m, seeded Gaussian noise added to every observed coordinate
  double sigma = 1e-4;       // m, observation noise standard deviation the filter assumes (R)
  int untilStep = 0;         // observations are used in steps 1 .. untilStep, then free run
  double timeOffset = 0.0;   // s, track time of the scene's t = 0
  // model_error: grows — the model error seen in the innovations (hidden points' radius) adds up
  // step by step after the last observation; constant — it stays as it was.
  bool modelErrorGrows = true;
  // tracks: stream — the markers come live from bcassim serve (OpenIGTLink); `tracks` is empty.
  bool streamed = false;
  // adaptive_noise: sigma re-estimated every step from the innovations; none: sigma is fixed.
  std::optional<AdaptiveNoiseSettings> adaptiveNoise;
  // frame_transform: the rigid motion from the observations' frame (a camera's, a tracker's) to
  // the model's, e.g. `bcassim register`'s transform.csv. The tracks and cloud frames above are
  // already moved by it; streamed markers are moved as they come. None: the model's frame.
  std::optional<RigidTransform> frameTransform;
};

struct AssimilationSettings {
  FilterKind filter = FilterKind::Roukf;
  SigmaPointKind sigmaPoints = SigmaPointKind::Simplex;
  double sigmaSpread = 1.0;  // ukf: spread alpha of the scaled unscented transform
  int members = 6;           // etkf ensemble size
  double inflation = 0.0;    // std of the additive noise on each parameter per step (unconstrained)
  std::uint64_t seed = 1;    // observation noise and etkf draws
  int threads = 1;           // executor workers
  // A step whose forecasts fail (a sigma point inverts an element even at time.min_dt) is redone
  // with the points halfway to the mean, up to this many times (FilterOptions::forecastRetries).
  int forecastRetries = 3;
  // Static frames with roukf: a frame whose analysis moves the mean by more than
  // reforecastBeyond forecast standard deviations is forecast again about it and analysed again,
  // up to this many times (RoukfOptions::reforecasts); 0: never.
  int reforecasts = 0;
  double reforecastBeyond = 1.0;  // forecast standard deviations (Mahalanobis), -
  bool carryPositions = true;
  bool carryVelocities = true;
  bool reuseFactorization = true;  // thesis Alg. 4/5: factorized-pcg sharing worker 0's factor
  // tangent: mean — every forecast steps with the tangent of the analysed mean, factorised once
  // per refresh (FrozenTangent; a Rosenbrock-W step) instead of assembling and solving its own.
  bool meanTangent = false;
  int tangentRefreshEvery = 1;       // steps between two mean tangents
  bool tangentInBackground = false;  // build it while the next steps run (older)
  // Steps a background build is given before it is adopted (1..tangentRefreshEvery); 0: 1 for
  // dynamic steps, tangentRefreshEvery for static frames.
  int tangentBackgroundSteps = 0;
  bool tangentSinglePrecision = false;  // tangent_precision: single — solves with L in float
  std::vector<EstimatedParameter> parameters;
  ObservationSettings observations;
  std::optional<TrackFrames> validationTruth;  // truth positions of the validation points, m
  // Bad input the run goes around (an empty frame, points that are not finite, frames out of
  // order), one line each naming the file and what was done; the runner adds its own per step.
  std::vector<std::string> notices;
};

}  // namespace bcassim
