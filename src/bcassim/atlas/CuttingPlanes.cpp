#include "bcassim/atlas/CuttingPlanes.h"

#include <Eigen/Geometry>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

CuttingPlaneFamily radialPlanes(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                                const Eigen::Vector3d& reference,
                                const std::vector<double>& angles) {
  if (!(axis.norm() > 0.0)) throw InputError("radial cutting planes: the axis is zero");
  CuttingPlaneFamily f;
  f.kind = CuttingPlaneFamily::Kind::Radial;
  f.centre = centre;
  f.axis = axis.normalized();
  const Eigen::Vector3d u = reference - reference.dot(f.axis) * f.axis;
  if (!(u.norm() > 1e-12 * reference.norm())) {
    throw InputError("radial cutting planes: the reference direction is parallel to the axis");
  }
  f.reference = u.normalized();
  const Eigen::Vector3d w = f.axis.cross(f.reference);  // angle pi/2
  for (double a : angles) {
    CuttingPlane p;
    p.point = centre;
    p.radial = std::cos(a) * f.reference + std::sin(a) * w;
    p.normal = f.axis.cross(p.radial);  // in the plane: axis and radial
    p.parameter = a;
    f.planes.push_back(p);
  }
  return f;
}

std::vector<double> evenAngles(double first, double last, int n) {
  if (n < 1) throw InputError("cutting planes: need at least one plane");
  std::vector<double> a(static_cast<size_t>(n), first);
  for (int k = 1; k < n; ++k) a[k] = first + (last - first) * k / (n - 1);
  return a;
}

CuttingPlaneFamily parallelPlanes(const Eigen::Vector3d& origin, const Eigen::Vector3d& normal,
                                  const std::vector<double>& offsets) {
  if (!(normal.norm() > 0.0)) throw InputError("parallel cutting planes: the normal is zero");
  CuttingPlaneFamily f;
  f.kind = CuttingPlaneFamily::Kind::Parallel;
  f.centre = origin;
  f.axis = normal.normalized();
  for (double d : offsets) {
    CuttingPlane p;
    p.point = origin + d * f.axis;
    p.normal = f.axis;
    p.parameter = d;
    f.planes.push_back(p);
  }
  return f;
}

CuttingPlaneFamily transformed(const CuttingPlaneFamily& family, const Eigen::Matrix3d& R,
                               const Eigen::Vector3d& t) {
  CuttingPlaneFamily f = family;
  f.centre = R * family.centre + t;
  f.axis = R * family.axis;
  f.reference = R * family.reference;
  for (CuttingPlane& p : f.planes) {
    p.point = R * p.point + t;
    p.normal = R * p.normal;
    p.radial = R * p.radial;
  }
  return f;
}

}  // namespace bcassim
