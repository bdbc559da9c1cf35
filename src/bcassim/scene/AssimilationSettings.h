// The `assimilation:` section of a scene (docs/assimilation-format.md): which filter estimates
// which model parameters from which observed tracks, and what truth the result is validated on.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bcassim/assimilation/ParameterTransform.h"
#include "bcassim/assimilation/SigmaPointSet.h"
#include "bcassim/io/CsvTracks.h"
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
};

// Positions on the scene's time grid: frame k holds the positions at time timeOffset + k dt,
// NaN rows for points not seen. Frames absent from the file are NaN throughout.
struct TrackFrames {
  std::string file;                      // as resolved, for messages
  std::vector<Eigen::MatrixX3d> frames;  // index k = 0 .. steps; k = 0 is the rest state
  std::vector<bool> present;             // frame k was in the file
};

struct ObservationSettings {
  TrackFrames tracks;        // observed marker positions, m
  double noiseStddev = 0.0;  // m, seeded Gaussian noise added to every observed coordinate
  double sigma = 1e-4;       // m, observation noise standard deviation the filter assumes (R)
  int untilStep = 0;         // observations are used in steps 1 .. untilStep, then free run
  double timeOffset = 0.0;   // s, track time of the scene's t = 0
};

struct AssimilationSettings {
  FilterKind filter = FilterKind::Roukf;
  SigmaPointKind sigmaPoints = SigmaPointKind::Simplex;
  double sigmaSpread = 1.0;  // ukf: spread alpha of the scaled unscented transform
  int members = 6;           // etkf ensemble size
  double inflation = 0.0;    // std of the additive noise on each parameter per step (unconstrained)
  std::uint64_t seed = 1;    // observation noise and etkf draws
  int threads = 1;           // executor workers
  bool carryPositions = true;
  bool carryVelocities = true;
  bool reuseFactorization = true;  // thesis Alg. 4/5: factorized-pcg sharing worker 0's factor
  // tangent: mean — every forecast steps with the tangent of the analysed mean, factorised once
  // per refresh (FrozenTangent; a Rosenbrock-W step) instead of assembling and solving its own.
  bool meanTangent = false;
  int tangentRefreshEvery = 1;       // steps between two mean tangents
  bool tangentInBackground = false;  // build it while the next step runs (one step older)
  std::vector<EstimatedParameter> parameters;
  ObservationSettings observations;
  std::optional<TrackFrames> validationTruth;  // truth positions of the validation points, m
};

}  // namespace bcassim
