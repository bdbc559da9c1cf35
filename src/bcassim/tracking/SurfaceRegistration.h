// Rigid registration of a point cloud to a triangle surface without correspondences: trimmed
// point-to-plane ICP from several start rotations, for partial views (20-40 % of an organ).
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// The identity, then rotations by +-45 and +-90 degrees about the x, y and z axes.
std::vector<Eigen::Matrix3d> defaultStartRotations();

struct SurfaceRegistrationOptions {
  RigidTransform initial;  // first guess, points' frame -> surface frame
  // ICP starts: each rotation about the centroid of the initially moved points, after `initial`.
  std::vector<Eigen::Matrix3d> startRotations = defaultStartRotations();
  int probeIterations = 10;  // ICP iterations from every start; the best start is refined
  int maxIterations = 100;   // of the refinement
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
  int start = 0;             // the start refined: index into startRotations
};

// Moves `points` (#P by 3, m, finite, #P >= 6) onto `surface` (m, #F >= 1) by minimising the
// trimmed sum of squared distances to the tangent planes at their closest surface points (found
// with an AABB tree). Every start runs probeIterations; the start with the smallest median
// distance over all points (ties: the earlier start) is refined to convergence. Throws
// InputError for bad inputs or options, including points and surface in different units
// (requireMatchingUnits).
SurfaceRegistration registerPointsToSurface(const Eigen::MatrixX3d& points, const TriMesh& surface,
                                            const SurfaceRegistrationOptions& options = {});

}  // namespace bcassim
