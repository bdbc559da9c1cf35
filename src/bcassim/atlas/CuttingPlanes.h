// Cutting planes for ligament-curve statistics (thesis §4.3.3, §5.2): radial half-planes that
// contain an axis through the organ centre (falciform), or parallel planes along a direction.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace bcassim {

struct CuttingPlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // a point of the plane (m)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit normal
  // Radial half-plane: only points p with (p - point).radial >= 0 belong to it; zero vector: the
  // whole plane.
  Eigen::Vector3d radial = Eigen::Vector3d::Zero();
  double parameter = 0.0;  // angle (rad) of a radial plane, offset (m) of a parallel one
};

struct CuttingPlaneFamily {
  enum class Kind { Radial, Parallel } kind = Kind::Radial;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();      // radial: on the axis; parallel: offset 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();       // radial: common line; parallel: normal
  Eigen::Vector3d reference = Eigen::Vector3d::UnitY();  // radial: direction of angle 0
  std::vector<CuttingPlane> planes;
};

// Half-planes bounded by the line {centre + t axis}, at angles[k] (rad) from `reference` turning
// right-handed about `axis` (reference is made orthogonal to axis). Throws InputError on a zero
// axis or a reference parallel to it.
CuttingPlaneFamily radialPlanes(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                                const Eigen::Vector3d& reference,
                                const std::vector<double>& angles);

// n evenly spaced angles covering [first, last] (rad), n >= 1 (n == 1: first).
std::vector<double> evenAngles(double first, double last, int n);

// Planes {p : (p - origin).normal = offsets[k]}. Throws InputError on a zero normal.
CuttingPlaneFamily parallelPlanes(const Eigen::Vector3d& origin, const Eigen::Vector3d& normal,
                                  const std::vector<double>& offsets);

// The same family moved to another frame: centre and plane points mapped by x -> R x + t,
// directions by R (e.g. from the template onto a rigidly aligned patient).
CuttingPlaneFamily transformed(const CuttingPlaneFamily& family, const Eigen::Matrix3d& R,
                               const Eigen::Vector3d& t);

}  // namespace bcassim
