// Rigid registration of a point cloud to a triangle surface without correspondences: trimmed
// point-to-plane ICP from several start rotations, for partial views (20-40 % of an organ).
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// The identity, then rotations by 25, 50 and 90 degrees about 14 axes (the 6 coordinate
// directions and the 8 cube diagonals), then half turns about x, y and z: 46 starts. Every
// rotation of up to 30 degrees lies within 17 degrees of one of them, up to 60 within 34
// (sampled).
std::vector<Eigen::Matrix3d> defaultStartRotations();

struct SurfaceRegistrationOptions {
  RigidTransform initial;  // first guess, points' frame -> surface frame
  // ICP starts: each rotation about the centroid of the initially moved points, after `initial`.
  std::vector<Eigen::Matrix3d> startRotations = defaultStartRotations();
  // Every start is probed with probeIterations ICP iterations on at most probePoints of the
  // points (evenly spaced rows); the refinedStarts best probes go on to convergence on those
  // points, and the best of them is refined on all points. "Best": the smallest mean of
  // min(distance, cap)^2 over the closest keepFraction of the points, one cap for all the runs
  // compared (medianFactor x their smallest median): a pose gains nothing by trimming points
  // away. A dozen markers on a smooth organ give ICP several minima a few millimetres apart in
  // residual: refining a single probe settled in the wrong one (LiTS-11 of pipeline-tracked).
  int probeIterations = 30;
  int probePoints = 500;
  int refinedStarts = 4;
  int maxIterations = 100;  // of each refinement
  // Trimming, applied every iteration to the point-to-surface distances: at most keepFraction
  // (0 < f <= 1) of the points are kept, the closest ones (trimmed ICP: set it to the expected
  // inlier fraction), and none farther than medianFactor times the median distance (0: no such
  // limit), a limit never below minThreshold (m) so that exact data keep all their points.
  double keepFraction = 1.0;
  double medianFactor = 3.0;
  double minThreshold = 1e-4;  // m
  double tolerance = 1e-10;    // m: stop when an iteration moves no point by more than this
};

struct SurfaceRegistration {
  RigidTransform transform;  // points' frame -> surface frame
  double rms = 0.0;          // m: RMS distance of the kept points to the surface, at the end
  double overlap = 0.0;      // kept points / all points, at the end
  int iterations = 0;        // ICP iterations of the refinement
  // The refinement met the tolerance before maxIterations; if not, lastMove (m) says how far its
  // last iteration still moved a point (a pose sliding slowly along a smooth surface).
  bool converged = false;
  double lastMove = 0.0;
  int start = 0;  // the start that won: index into startRotations
};

// Moves `points` (#P by 3, m, finite, #P >= 6) onto `surface` (m, #F >= 1) by minimising the
// trimmed sum of squared distances to the tangent planes at their closest surface points (found
// with an AABB tree), from every start as the options say (ties: the earlier start). Throws
// InputError for bad inputs or options, including points and surface in different units
// (requireMatchingUnits).
SurfaceRegistration registerPointsToSurface(const Eigen::MatrixX3d& points, const TriMesh& surface,
                                            const SurfaceRegistrationOptions& options = {});

}  // namespace bcassim
