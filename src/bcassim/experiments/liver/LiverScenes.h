// The three scenes of the liver experiment (thesis §5.1) built in code from one set of values:
// the ground truth (fine Ogden liver, dense ligament springs), the estimation (coarse StVK liver,
// K spring groups, ROUKF) and the baseline (the ligament as fixed nodes). The scene files written
// for the user (LiverSceneFiles.h) come from the same values. SI units.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bcassim/experiments/liver/LiverScenario.h"
#include "bcassim/mechanics/materials/OgdenMaterial.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

// The files of the atlas band's edges beside the prepared scenes (LiverSceneSpec::springBand*).
inline constexpr const char* kSpringBandLowerFile = "spring_band_lower.csv";
inline constexpr const char* kSpringBandUpperFile = "spring_band_upper.csv";

// What the scenes are made of, beyond the options they were prepared with.
struct LiverSceneSpec {
  LiverScenarioOptions options;  // dt, steps, groups, ligament length, threads, noise, ...
  std::string dir;               // where the scene files and the files they name are written
  std::string sourceName;        // the surface ("phantom" or its file name), for the files
  LiverAnatomy anatomy;          // the frame, the vessels' sphere, the loaded regions
  std::shared_ptr<const TetMesh> fine, coarse;  // fine.vtu (truth), coarse.vtu (the others)
  Eigen::MatrixX3d curve;                       // falciform attachment curve, m (curve.csv)
  // The curve the estimation's springs and the baseline's fixed nodes follow: `curve` itself,
  // or in atlas mode the atlas' mean curve on this liver (spring_curve.csv).
  Eigen::MatrixX3d springCurve;
  std::string springCurveFile = "curve.csv";
  // Atlas mode with its band: the two edges the estimation's layers follow (LigamentOptions'
  // bandLower/bandUpper; spring_band_lower.csv, spring_band_upper.csv); empty otherwise.
  Eigen::MatrixX3d springBandLower, springBandUpper;
  Eigen::MatrixX3d markers;              // observed points at rest, m (markers.csv)
  Eigen::MatrixX3d validation;           // inner points, never observed, m (validation.csv)
  Eigen::MatrixX3d tumours;              // hidden points, m (tumours.csv)
  std::vector<int> ligamentNodes;        // baseline: coarse nodes held in place of the ligament
  double rightForce = 0, leftForce = 0;  // peak loads, N: right lobe down, left lobe anterior

  // Thesis §5.1: Ogden liver (alpha 0.88, G 7.21 kPa, i.e. FEBio c = 16.47 kPa), nu 0.49; the
  // estimation model is StVK, 15 kPa.
  double truthShear = 7210.0;  // Pa
  double truthAlpha = 0.88;
  double truthPoisson = 0.49;
  double estimationYoung = 15000.0;  // Pa
  double estimationPoisson = 0.49;
  double density = 1000.0;                              // kg/m^3
  double rayleighMass = 1.0, rayleighStiffness = 0.02;  // 1/s, s
  double solverTolerance = 1e-8;                        // factorized-pcg, relative residual
  int truthRefreshEvery = 10;                           // truth: matrices between factorisations
  double truthSpacing = 0.002;  // m between truth springs along the curve: a dense "membrane"
  int outputEvery = 20;         // steps between ParaView frames
  // Spring coefficients per group [k_alpha N/m^3, 0, k_gamma N/m]: the truth's vary along the
  // curve, the estimation's start from the prior.
  std::vector<CubicSpringCoefficients> truthGroups, estimationGroups;
  double priorStiffness = 0;  // prior mean of each k_gamma, N/m
  double priorStddev = 0;     // its standard deviation, N/m
  // Bounds of each estimated k_gamma (transform bounded-log), N/m, and its random walk in the
  // scene's unit (N/m per s^0.5: the relative walk times the prior, the log-space walk at the
  // prior, which is the bounds' geometric centre).
  double stiffnessLower() const { return priorStiffness / kStiffnessBoundFactor; }
  double stiffnessUpper() const { return priorStiffness * kStiffnessBoundFactor; }
  double stiffnessRandomWalk() const { return options.stiffnessRandomWalk * priorStiffness; }
  // The truth lies within a factor 4 of the prior (0.4 to 1.6 times 1/priorFactor = 2.5 its
  // mean); springs 1000 times stiffer than that hold the liver like fixed nodes and 1000 times
  // softer ones barely at all, so the markers cannot tell values beyond these apart: bounding
  // there loses nothing the data could identify and stops the excursions of weakly observed groups
  // (issue 15: k_gamma_8 at 1.4e10 N/m in the demo).
  static constexpr double kStiffnessBoundFactor = 1e3;
  int estimationSprings = 0;  // springs of the estimation model (for the file's comment)

  // Truth: Ogden with the bulk modulus that makes the small-strain Poisson ratio truthPoisson.
  OgdenMaterial truthMaterial() const;
  // Observation noise standard deviation the filter assumes (R), m.
  double observationSigma() const;
  std::string scenePath(const std::string& file) const;  // dir/file
};

// The values of the scenes from an annotated surface: what prepareLiverScenario does (see it)
// up to, not including, building the scenes and writing their .yaml files; `report` gets the
// meshing report, anatomy, curve length, fixed nodes and loads. Other experiments built on the
// liver (experiments/tracked) change the values before building their scenes.
// `log` gets the progress lines of an atlas built in atlas mode (minutes).
LiverSceneSpec prepareLiverSceneSpec(const LiverScenarioOptions& options, const std::string& outDir,
                                     LiverScenario& report,
                                     const std::function<void(const std::string&)>& log = {});

// The coarse liver's mechanics alone (mesh, StVK, density; no damping, boundary conditions or
// springs): the estimation and baseline models, and the load calibration.
MechanicalModel makeCoarseLiverModel(const LiverSceneSpec& spec);

// The nodes of `mesh` in a sphere (m); throws InputError naming `what` when there is none.
std::vector<int> sphereNodes(const TetMesh& mesh, const Vec3& center, double radius,
                             const std::string& what);

// The scenes, as loadScene reads dir/truth.yaml, estimate.yaml and baseline.yaml. The
// estimation scene's assimilation has no tracks yet: they come from the truth run
// (withTruthTracks).
Scene makeLiverTruthScene(const LiverSceneSpec& spec);
Scene makeLiverEstimationScene(const LiverSceneSpec& spec);
Scene makeLiverBaselineScene(const LiverSceneSpec& spec);

// `estimation` with its observed tracks (truthDir/markers.csv) and validation truth
// (truthDir/validation.csv) put on its time grid, as estimate.yaml names them. Throws InputError
// for missing or mismatched files.
Scene withTruthTracks(Scene estimation, const std::string& truthDir);

}  // namespace bcassim
