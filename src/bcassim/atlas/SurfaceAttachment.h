// Points attached to a surface by barycentric coordinates (thesis §4.3.3): ligament curves and
// statistics on one shape follow its deformation onto another shape of the same connectivity.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

class SurfaceAttachment {
 public:
  SurfaceAttachment() = default;  // no points
  // Projects each row of points (#p by 3) to its closest point on surface. Throws InputError on a
  // surface without faces.
  SurfaceAttachment(const TriMesh& surface, const Eigen::MatrixX3d& points);

  // Points stored as barycentric coordinates: corners (#p by 3 vertex ids) and weights (#p by 3,
  // rows summing to 1), e.g. read back from a file. Throws InputError on mismatched sizes or
  // negative ids.
  SurfaceAttachment(Eigen::MatrixX3i corners, Eigen::MatrixX3d weights);

  Eigen::Index size() const { return corners_.rows(); }
  const Eigen::MatrixX3i& corners() const { return corners_; }
  const Eigen::MatrixX3d& weights() const { return weights_; }

  // Attached points on the surface with vertices moved to V (#V by 3, same faces): #p by 3.
  Eigen::MatrixX3d positions(const Eigen::MatrixX3d& V) const;

  // Distance of each input point to the surface it was projected on (m), #p (zeros when built
  // from stored coordinates).
  const Eigen::VectorXd& projectionDistances() const { return distance_; }

 private:
  Eigen::MatrixX3i corners_;  // #p by 3 vertex indices of the face holding each point
  Eigen::MatrixX3d weights_;  // #p by 3 barycentric weights
  Eigen::VectorXd distance_;
};

}  // namespace bcassim
