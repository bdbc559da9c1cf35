// The thesis' liver experiment (§5.1) set up from one annotated CT surface: a fine ground-truth
// model (Ogden, dense ligament springs), a coarse estimation model (StVK, K spring groups), and a
// baseline whose ligament is fixed nodes: three scenes built in code (and written as scene files
// for the user) sharing markers, validation points, tumours, loads and the vessel region. Metres.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "bcassim/Types.h"
#include "bcassim/ligaments/SurfaceMesher.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

// Stands for the built-in phantom (LiverPhantom.h) where a surface path is expected.
inline constexpr const char* kLiverPhantomName = "phantom";

struct LiverScenarioOptions {
  // Closed triangle surface (.obj, ...), in `scale` units, or kLiverPhantomName.
  std::string surface;
  std::string eseg;  // edge labels (.eseg); empty: the surface's path with .eseg
  // Atlas mode (thesis §4.3, §5.2; a patient without annotation): the estimation's springs and
  // the fixed-ligament baseline follow the falciform curve of a ligament atlas transferred onto
  // this liver, never its annotation. `atlas`: a folder of `bcassim atlas build`; with
  // `atlasLivers` (annotated livers) an atlas built without this liver, cached in `atlas`
  // (default OUT/atlas). The .eseg, when there is one, then only gives the truth's ligament (and
  // the curve's distance reported); without it the truth's ligament follows the atlas curve too.
  std::string atlas, atlasLivers;
  int atlasTransferIterations = 100;  // L-BFGS iterations of the transfer's registration
  // Atlas mode: the estimation's two layers of springs on the edges of the atlas' band (its mean
  // curve -/+ sigma on this liver) instead of +-4 mm about its mean curve: spread over where the
  // ligament may lie (thesis §4.3's band). The baseline's fixed nodes stay on the mean curve.
  bool atlasBand = false;
  // Priors of the estimation's springs from a measured tissue: a springs.yaml of `bcassim ligament
  // springs` (its coefficients >= 0, per metre of width, scaled to ligamentLength): k_gamma's
  // mean and standard deviation, k_alpha and k_beta as the known nonlinear terms. Empty: the
  // prior is priorFactor times the truth's mean stiffness and the cubic term from
  // stiffeningStretch.
  std::string springPriors;
  // How far a patient's ligament may be from the prior, relative to its mean: each k_gamma's
  // prior standard deviation is sqrt(sigma^2 + (priorSpread mean)^2), sigma the calibration's own
  // (how well its data fixed the mean; 0 without springPriors).
  double priorSpread = 1.0;
  double scale = 1e-3;     // m per surface unit (the CT livers are in mm)
  int coarseNodes = 2150;  // estimation mesh (thesis: 2,150)
  int fineNodes = 14000;   // ground-truth mesh (thesis: ~14,300)
  int markers = 14;        // observed, on the anterior surface
  int validationPoints = 12;
  int tumours = 3;
  int groups = 10;               // estimated spring groups K (ROUKF: K + 1 sigma points)
  double ligamentLength = 0.03;  // extrusion = rest length, m
  // Ligament stiffness of the truth per metre of attachment curve, both layers together (N/m per
  // m); it varies along the curve between 0.4 and 1.6 times this. The estimation starts from
  // priorFactor times its mean.
  double ligamentStiffness = 300;
  double priorFactor = 0.4;
  // Random walk of each estimated k_gamma, relative: the standard deviation of its logarithm
  // grows by this per sqrt(s) (1/s^0.5; 0.3: 30 % after 1 s) and keeps growing once the
  // observations stop. Off by default: on the LiTS-3 demo 0.3 raised the validation error from
  // 1.19 to 1.40 mm, and the tumours' radius it widens follows the loads rather than growing every
  // step (docs/liver.md).
  double stiffnessRandomWalk = 0.0;
  double stiffeningStretch = 0.01;  // m: at this stretch the cubic term equals the linear one
  // Loads: right lobe pushed down (half sine, period 4 s), left lobe up then down (sine, 3 s).
  // Peak forces in N; 0: chosen so that the coarse model held by the vessels alone moves each
  // lobe by lobeDisplacement under it (static), so every liver deforms alike.
  double rightLobeForce = 0, leftLobeForce = 0;
  double lobeDisplacement = 0.02;  // m
  double dt = 0.02;                // s
  int steps = 400;
  int observedSteps = 300;  // observations in steps 1 .. observedSteps, then free run
  double noise = 5e-4;      // m, Gaussian noise on the observed tracks
  int threads = 2;
};

// Directions found from the shape and the annotations (the CT frames differ between livers):
// `lateral` is the normal of the falciform ligament's plane (spanned by the curve's main
// direction and the outward surface normal along it), towards the larger (right) lobe;
// `anterior` is that surface normal (where the ligament goes) and `superior` points from the
// ridge (label 3, the anterior-inferior border) to the ligament, both in the plane.
struct LiverAnatomy {
  Vec3 center = Vec3::Zero();
  Vec3 lateral = Vec3::UnitX(), anterior = Vec3::UnitY(), superior = Vec3::UnitZ();
  // Centre of the fixed vessel region: the surface point nearest the centre on the visceral side
  // (the porta hepatis notch).
  Vec3 hilum = Vec3::Zero();
  double vesselRadius = 0.012;  // m, grown until the sphere holds 12 nodes of the coarse mesh
  Vec3 rightLoad = Vec3::Zero(), leftLoad = Vec3::Zero();  // centres of the loaded regions
  double loadRadius = 0.03;
  bool ridgeFound = false;
};

// Where the estimation's springs came from in atlas mode.
struct LiverAtlasSprings {
  bool used = false;
  std::string source;          // the atlas folder, or "N livers without NAME"
  bool band = false;           // the springs on the edges of its band (--atlas-band)
  double rotationDegrees = 0;  // of the template's rigid alignment onto this liver
  double buildSeconds = 0, transferSeconds = 0;
  double meanSigma = 0;  // m, mean standard deviation of the transferred curve (its band)
  // Distance of the springs' curve from the expert's (m, per point of the springs' curve); -1:
  // no annotation to compare with.
  double expertDistanceMean = -1, expertDistanceMax = -1;
};

struct LiverScenario {
  std::string dir;  // where the files went
  LiverAnatomy anatomy;
  LiverAtlasSprings atlas;
  bool annotated = true;  // the truth's ligament is the expert's (.eseg), not the atlas curve
  SurfaceMeshingReport coarse, fine;
  double curveLength = 0;  // m
  int fixedNodes = 0;      // baseline: coarse nodes held in place of the ligament
  double priorStiffness = 0, priorStddev = 0;  // N/m: each estimated k_gamma's prior
  double rightForce = 0, leftForce = 0;        // peak loads used, N
  // The three scenes, built in code (LiverScenes.h); the .yaml files say the same for the user.
  // The estimation scene has no tracks until the truth has run (withTruthTracks).
  std::shared_ptr<const Scene> truthScene, estimateScene, baselineScene;
};

// Meshes the surface twice, derives the anatomy, picks the points, builds the three scenes and
// writes to outDir: coarse.vtu, fine.vtu, curve.csv, markers.csv, validation.csv, tumours.csv,
// anatomy.csv (the frame: centre, anterior, superior, lateral) and the scenes for the user,
// truth.yaml (run first: simulate), estimate.yaml (assimilate) and baseline.yaml (simulate).
// Throws InputError for unreadable or unmeshable input.
// In atlas mode the atlas is transferred (and built when asked: `log` gets its progress lines).
LiverScenario prepareLiverScenario(const LiverScenarioOptions& options, const std::string& outDir,
                                   const std::function<void(const std::string&)>& log = {});

}  // namespace bcassim
