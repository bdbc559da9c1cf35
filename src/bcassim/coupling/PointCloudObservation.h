// A partial surface seen as unlabelled points (thesis §5.3, issue 14): each point observes its
// closest point on the model's surface, found again every step on the forecast mean's surface
// (face and barycentric weights, AABB tree) and fixed for every sigma point of the step.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/assimilation/ObservationOperator.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/scene/AssimilationSettings.h"

namespace bcassim {

// What the last linearize() did with its frame, for filter.csv.
struct PointCloudStepStats {
  int points = 0;               // points in the frame
  int used = 0;                 // within the cutoff (0 when fewer than min_points were)
  double medianDistance = 0.0;  // m, of the frame's closest keep_fraction of points to the mean's
                                // surface
  // m, max(distance_factor x median, min_distance), at most max_distance and the distance of
  // the last of the keep_fraction closest points
  double cutoff = 0.0;
};

class PointCloudObservation final : public ObservationOperator {
 public:
  // `surface`: the observed triangles by node ids of a mesh of `nodes` nodes, whose positions
  // (3 x nodes, node-major, m) are the forecasts' observables. Throws InputError when a triangle
  // names a node out of range or the surface has none.
  PointCloudObservation(Eigen::MatrixX3i surface, Eigen::Index nodes,
                        const PointCloudSettings& settings);

  // `frame`: x, y, z of every point (3 entries per point, m) with their noise variances; a
  // point is present when its x is. Points farther than the cutoff from the mean's surface are
  // marked absent; with fewer than min_points left, all are (the step is then a prediction).
  // Residual normal: one entry per point, the coordinate along the normal of the mean's face at
  // the closest point (its noise: the variance of x); residual point: the frame's three.
  Observation linearize(const Eigen::VectorXd& meanObservable, const Observation& frame) override;
  // The closest points' positions on this forecast's surface (same faces and weights), or their
  // coordinate along the fixed normals.
  void predict(const Eigen::VectorXd& observable, Eigen::VectorXd& predicted) const override;

  const PointCloudStepStats& lastStats() const { return stats_; }
  // Nodes of the observed surface (sorted, unique), e.g. for a unit check of a frame.
  Eigen::MatrixX3d surfacePositions(const Eigen::VectorXd& positions) const;

 private:
  Vec3 pointOn(int i, const Eigen::VectorXd& positions) const;

  Eigen::MatrixX3i surface_;
  Eigen::Index nodes_;
  CloudResidual residual_;
  double distanceFactor_, minCutoff_, maxCutoff_, keepFraction_;
  int minPoints_;
  // Fixed by linearize(), per frame point.
  std::vector<int> face_;
  std::vector<Vec3> weights_, normal_;
  PointCloudStepStats stats_;
  // Built at the first linearize(), refitted to the mean's surface at the next ones.
  std::optional<SurfaceLocator> locator_;
};

}  // namespace bcassim
