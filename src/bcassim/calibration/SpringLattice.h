// A layer of cubic springs over a box (thesis §2.3.4, Fig. 2.15): every edge and both diagonals
// of every face of a grid of hexahedral cells (6 edge + 12 diagonal springs around each node),
// tension-only springs of eq. 2.26 sharing one set of coefficients. Lengths in metres.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/CubicSpringSet.h"

namespace bcassim {

struct LatticeSpring {
  int a = 0, b = 0;       // node indices
  double restLength = 0;  // m
  bool diagonal = false;  // a face diagonal (else a grid edge)
};

class SpringLattice {
 public:
  // Box [0,sx]x[0,sy]x[0,sz] cut into nx*ny*nz cells; node (i,j,k) has index
  // i + (nx+1)*(j + (ny+1)*k), as in makeBoxMesh. Throws InputError for a non-positive size or
  // count.
  SpringLattice(const Vec3& size, int nx, int ny, int nz);

  int numNodes() const { return static_cast<int>(rest_.size() / 3); }
  int node(int i, int j, int k) const { return i + (nx_ + 1) * (j + (ny_ + 1) * k); }
  int cells(int axis) const { return axis == 0 ? nx_ : (axis == 1 ? ny_ : nz_); }
  const Vec3& size() const { return size_; }
  const Eigen::VectorXd& restPositions() const { return rest_; }  // 3N, node-major
  const std::vector<LatticeSpring>& springs() const { return springs_; }

  // Stored energy (J) of positions x (3N) with coefficients k.
  double energy(const Eigen::VectorXd& x, const CubicSpringCoefficients& k) const;
  // Spring s at positions x: false when slack (no force, no stiffness); else its force on node b
  // (N; -force on node a) and, when H is not null, d(force)/d(x_b) (N/m; the stiffness blocks
  // are H on aa and bb, -H on ab and ba).
  bool springForce(const Eigen::VectorXd& x, const CubicSpringCoefficients& k, size_t s,
                   Vec3& force, Mat3* H) const;
  // Internal forces dW/dx (N, 3N) and, when K is not null, the stiffness d2W/dx2 (N/m) as
  // triplets (K is cleared first).
  void forces(const Eigen::VectorXd& x, const CubicSpringCoefficients& k, Eigen::VectorXd& f,
              std::vector<Eigen::Triplet<double>>* K = nullptr) const;

 private:
  Vec3 size_;
  int nx_, ny_, nz_;
  Eigen::VectorXd rest_;
  std::vector<LatticeSpring> springs_;
};

}  // namespace bcassim
