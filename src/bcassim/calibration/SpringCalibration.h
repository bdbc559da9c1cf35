// Spring coefficients from a FEM membrane (thesis §2.3.4, §4.4): ROUKF estimates the cubic
// coefficients (k_alpha, k_beta, k_gamma) of a spring lattice so that it reproduces the stretch of
// a hyperelastic strip; the two are then compared under the membrane's force and timed frame by
// frame, and the strip's force law becomes priors per metre of ligament. SI units throughout.
#pragma once
#include <array>
#include <vector>

#include "bcassim/calibration/MembraneStrip.h"
#include "bcassim/mechanics/CubicSpringSet.h"

namespace bcassim {

struct SpringCalibrationOptions {
  MembraneOptions membrane;  // the truth: size, material, mesh
  double strain = 0.45;      // largest engineering strain of the stretch, in (0, 1]
  // Quasi-static frames from 0 to `strain`, equal increments (9: 5 % each at 45 %). Finer
  // steps fit the first percent of strain worse (the lattice's reaction there is up to 16 % low
  // with 1 % steps, 0.02 N on the thesis' strip), at no gain elsewhere.
  int frames = 9;
  // Lattice cells across the width and along the length (one across the thickness); they must
  // divide the membrane's cells, so that every lattice node is a membrane node.
  int latticeX = 4, latticeY = 10;
  int passes = 5;  // loading passes (0 to `strain`) the filter sees, >= 1
  // Observation noise the filter assumes: on the reaction, relative to the frame's membrane
  // reaction; on the free lattice nodes' positions, m (0: not observed, the default: tension-only
  // springs neck where the membrane does not, and fitting that shape costs the force law).
  double forceSigma = 0.01;
  double positionSigma = 0;
};

// One frame of the stretch, membrane and the lattice with the estimated coefficients.
struct SpringFrame {
  double strain = 0, displacement = 0;  // -, m (the pulled end's)
  double membraneReaction = 0;          // N along y, pulled to `displacement`
  double latticeReaction = 0;           // N along y, pulled to `displacement`
  // The lattice under the membrane's reaction (its pulled end a rigid grip): where the grip goes
  // (m), and the distance of its nodes to the membrane's nodes at the same material points (m):
  // the pulled end's (the ligament's attachment, thesis Fig. 2.15's compared nodes) and all.
  double forceDrivenDisplacement = 0;
  double attachmentMeanError = 0, attachmentMaxError = 0;
  double meanError = 0, maxError = 0;
  // Wall time of the frame's solve, s (the lattice's: median of 5 repeats of the stretch).
  double membraneSeconds = 0, latticeSeconds = 0;
  int membraneIterations = 0, latticeIterations = 0;  // Newton iterations of that solve
};

struct CoefficientPrior {
  double mean = 0, stddev = 0;
};

struct SpringCalibrationResult {
  int membraneTets = 0, membraneNodes = 0;
  int latticeNodes = 0, edgeSprings = 0, diagonalSprings = 0;
  // Coefficients of one lattice spring (k_alpha N/m^3, k_beta N/m^2, k_gamma N/m): the filter's
  // start (least squares on the reactions with the lattice at the membrane's positions) and its
  // estimate, with standard deviations.
  CubicSpringCoefficients initial, estimated;
  Eigen::Vector3d initialStddev = Eigen::Vector3d::Zero(), stddev = Eigen::Vector3d::Zero();
  // Per filter step: the frame, the estimate and its standard deviations.
  std::vector<int> stepFrame;
  std::vector<Eigen::Vector3d> stepMean, stepStddev;
  std::vector<SpringFrame> frames;
  // m, over every frame, force-driven: at the pulled end's nodes (the thesis' comparison), and
  // at every lattice node
  double attachmentMeanError = 0, attachmentMaxError = 0;
  double meanError = 0, maxError = 0;
  // The last frame, force-driven: membrane and lattice positions at the lattice nodes (3N, m).
  Eigen::VectorXd lastMembrane, lastLattice;
  double maxReactionError = 0;  // max over frames of |R_lattice - R_membrane| / R_membrane
  double membraneMedianMs = 0, latticeMedianMs = 0, speedRatio = 0;  // per frame's solve
  // The same per Newton iteration (a frame's time over its iterations): the membrane's Newton
  // needs more iterations per frame than the lattice's, which the per-frame ratio includes.
  double membraneMedianMsPerIteration = 0, latticeMedianMsPerIteration = 0;
  double iterationSpeedRatio = 0;
  // The strip's reaction F(d) = Ka d^3 + Kb d^2 + Kg d (d its elongation, m) fitted to the
  // estimated lattice over the frames, divided by the width: the coefficients one metre of
  // ligament width gives a spring of rest length = the strip's length (N/m^3, N/m^2, N/m per m of
  // width), with standard deviations from the filter's covariance (unscented transform).
  std::array<CoefficientPrior, 3> perMetre;
  double perMetreFitError = 0;  // RMS of that fit's residual, relative to the largest reaction
  // The same with every coefficient >= 0 (the best of the fits on each subset of the three terms,
  // the others 0), which a scene's springs take: a softening law (Neo-Hookean's nominal stress)
  // makes the free fit's K_beta negative.
  std::array<CoefficientPrior, 3> perMetreNonNegative;
  double perMetreNonNegativeFitError = 0;
};

// Throws InputError for bad options, NumericalError when a solve fails.
SpringCalibrationResult calibrateSprings(const SpringCalibrationOptions& options);

}  // namespace bcassim
