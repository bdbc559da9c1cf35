// External loads: forces on node sets modulated in time, and "control points" (barycentric points
// pulled by stiff penalty springs along a prescribed trajectory, as the thesis drives its liver).
#pragma once
#include <optional>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mechanics/LoadFootprint.h"
#include "bcassim/mechanics/TimeProfile.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// force(t) = forcePerNode * profile(t) on every node of `nodes` (N per node); with `weights`
// (one per node; a surface traction's shares, summing to 1) node k gets weights[k] times that.
// With `frames` (a force given frame by frame, e.g. measured) forcePerNode(t) is read from them
// instead: frames[k] at t = (k + 1) frameDt, linear in between, from zero at t = 0, the last
// held after it.
struct NodalLoad {
  std::vector<int> nodes;
  Vec3 forcePerNode = Vec3::Zero();
  TimeProfile profile;
  std::vector<double> weights;  // empty: 1 for every node
  std::vector<Vec3> frames;     // N per node (times the weights); empty: forcePerNode
  double frameDt = 0.0;         // s, > 0 with frames
  // Set once a footprint coefficient is estimated: it then writes `weights` (LoadFootprint.h).
  std::optional<LoadFootprint> footprint;

  // The force per node at time t before the weights, N.
  Vec3 perNodeAt(double t) const;
  // The load's total force as forcePerNode stands (N): forcePerNode times the number of nodes,
  // or forcePerNode itself when the weights share it.
  Vec3 totalForce() const;
  // Sets component c (0, 1, 2 = x, y, z) of totalForce() to `newtons`.
  void setTotalForce(int c, double newtons);

  void addTo(double t, Eigen::VectorXd& f) const {
    const Vec3 force = perNodeAt(t);
    if (weights.empty()) {
      for (int n : nodes) f.segment<3>(3 * n) += force;
      return;
    }
    for (size_t k = 0; k < nodes.size(); ++k) f.segment<3>(3 * nodes[k]) += weights[k] * force;
  }
};

// Points mapped into the mesh, each pulled towards rest position + d(t) by a spring of stiffness
// `stiffness` (N/m); d(t) is linearly interpolated from (times, displacements), held at the ends.
class ControlPointSet {
 public:
  ControlPointSet(std::vector<MappedPoint> points, Eigen::MatrixX3d restPositions,
                  std::vector<double> times, Eigen::MatrixX3d displacements, double stiffness);

  Vec3 displacementAt(double t) const;
  double energy(const TetMesh& mesh, const Eigen::VectorXd& x, double t) const;
  void addInternalForces(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                         Eigen::VectorXd& f) const;
  void addForcesAndStiffness(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                             const AssemblyPattern& pattern, double scale, Eigen::VectorXd& f,
                             SparseMatrix& K) const;
  Eigen::Index size() const { return static_cast<Eigen::Index>(points_.size()); }

 private:
  std::vector<MappedPoint> points_;
  Eigen::MatrixX3d rest_;           // #points by 3, m
  std::vector<double> times_;       // s, increasing
  Eigen::MatrixX3d displacements_;  // #times by 3, m
  double stiffness_;                // N/m
};

}  // namespace bcassim
