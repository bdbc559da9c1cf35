// Tension-only cubic springs from points of the mesh (barycentric in a tet) to fixed anchors, the
// ligament model of thesis eq. 2.26: |f| = ka dl^3 + kb dl^2 + kg dl for dl > 0, else 0.
#pragma once
#include <limits>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/mechanics/AssemblyPattern.h"
#include "bcassim/mesh/TetMesh.h"

namespace bcassim {

// Coefficients shared by a group of springs: ka in N/m^3, kb in N/m^2, kg in N/m.
struct CubicSpringCoefficients {
  double kAlpha = 0, kBeta = 0, kGamma = 0;
};

struct CubicSpring {
  int tet = 0;            // tet holding the attachment point
  Vec4 weights;           // barycentric weights of the attachment point in that tet
  Vec3 anchor;            // fixed far end, m
  double restLength = 0;  // m
  int group = 0;          // index of the shared coefficients
};

class CubicSpringSet {
 public:
  CubicSpringSet() = default;
  CubicSpringSet(std::vector<CubicSpring> springs, std::vector<CubicSpringCoefficients> groups);

  // Force magnitude g(dl) (N) and its derivative (N/m) for length variation dl (m) (eq. 2.26).
  static double magnitude(const CubicSpringCoefficients& k, double dl);
  static double magnitudeDerivative(const CubicSpringCoefficients& k, double dl);
  static double potential(const CubicSpringCoefficients& k, double dl);  // integral of g, J

  // Energy (J), internal forces (gradient, N) and scale * stiffness at positions x and time t (s).
  // mesh gives each tet's nodes; K must have `pattern`'s structure.
  double energy(const TetMesh& mesh, const Eigen::VectorXd& x, double t) const;
  void addInternalForces(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                         Eigen::VectorXd& f) const;
  void addForcesAndStiffness(const TetMesh& mesh, const Eigen::VectorXd& x, double t,
                             const AssemblyPattern& pattern, double scale, Eigen::VectorXd& f,
                             SparseMatrix& K) const;

  const std::vector<CubicSpring>& springs() const { return springs_; }
  int numGroups() const { return static_cast<int>(groups_.size()); }
  const CubicSpringCoefficients& coefficients(int group) const { return groups_[group]; }
  void setCoefficients(int group, const CubicSpringCoefficients& k) { groups_[group] = k; }
  // From time t (s) on, the group's springs exert no force ("cut" ligament).
  void cutGroupAt(int group, double t) { cutTime_[group] = t; }
  double cutTime(int group) const { return cutTime_[group]; }
  // Coefficients in force at time t (zero after a cut).
  CubicSpringCoefficients activeCoefficients(int group, double t) const;
  // d(force on the attachment point)/d(attachment point) of spring s at x, t (N/m): zero when
  // slack; spread to its tet's nodes by the barycentric weights w_a w_b.
  Mat3 attachmentStiffness(const TetMesh& mesh, const Eigen::VectorXd& x, double t, size_t s) const;
  // Current attachment point of spring s, m.
  Vec3 attachment(const TetMesh& mesh, const Eigen::VectorXd& x, size_t s) const;

 private:
  std::vector<CubicSpring> springs_;
  std::vector<CubicSpringCoefficients> groups_;
  std::vector<double> cutTime_;
};

}  // namespace bcassim
