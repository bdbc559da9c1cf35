// Points attached to a surface by barycentric coordinates (thesis §4.3.3): ligament curves and
// statistics on one shape follow its deformation onto another shape of the same connectivity.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

class SurfaceAttachment {
 public:
  // Projects each row of points (#p by 3) to its closest point on surface. Throws InputError on a
  // surface without faces.
  SurfaceAttachment(const TriMesh& surface, const Eigen::MatrixX3d& points);

  // Attached points on the surface with vertices moved to V (#V by 3, same faces): #p by 3.
  Eigen::MatrixX3d positions(const Eigen::MatrixX3d& V) const;

  // Distance of each input point to the surface it was projected on (m), #p.
  const Eigen::VectorXd& projectionDistances() const { return distance_; }

 private:
  Eigen::MatrixX3i corners_;  // #p by 3 vertex indices of the face holding each point
  Eigen::MatrixX3d weights_;  // #p by 3 barycentric weights
  Eigen::VectorXd distance_;
};

}  // namespace bcassim
