// Objective of the LDDMM registration, thesis eqs. 4.6-4.7: E(a0) = w D(phi_a0(S), T) +
// a0^T K(q0, q0) a0, with phi_a0 the geodesic shot from (q0, a0) and its exact gradient in a0.
#pragma once
#include <Eigen/Core>

#include "bcassim/atlas/GeodesicShooting.h"
#include "bcassim/atlas/SurfaceDistance.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct RegistrationTerms {
  double data = 0.0;        // D(phi(S), T), unweighted
  double regularity = 0.0;  // a0^T K(q0, q0) a0 = squared geodesic length (eq. 4.6)
  double total = 0.0;       // w * data + regularity
};

class RegistrationObjective {
 public:
  // source: the mesh flowed (kept by reference, as are distance and shooting);
  // controlPoints: q0, #q by 3; dataWeight: w > 0 (1 / sigma_W^2 in eq. 4.7).
  RegistrationObjective(const TriMesh& source, const SurfaceDistance& distance,
                        const GeodesicShooting& shooting, Eigen::MatrixX3d controlPoints,
                        double dataWeight);

  // Terms at momenta a0 (#q by 3); when grad is non-null it receives dE/da0 (#q by 3),
  // exact for the discrete shooting scheme.
  RegistrationTerms evaluate(const Eigen::MatrixX3d& a0, Eigen::MatrixX3d* grad = nullptr) const;

  // Same with the source vertices replaced by V (#V by 3, the source's faces), as the atlas of
  // eq. 4.8 moves them; gradV (when non-null) receives dE/dV (#V by 3).
  RegistrationTerms evaluateAt(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& a0,
                               Eigen::MatrixX3d* gradA, Eigen::MatrixX3d* gradV) const;

  // Source vertices flowed by the geodesic from a0: #V by 3.
  Eigen::MatrixX3d deform(const Eigen::MatrixX3d& a0) const;

  const Eigen::MatrixX3d& controlPoints() const { return q0_; }

 private:
  const TriMesh& source_;
  const SurfaceDistance& distance_;
  const GeodesicShooting& shooting_;
  Eigen::MatrixX3d q0_;
  double weight_;
};

}  // namespace bcassim
