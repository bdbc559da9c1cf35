// Correspondence-free data term between a deformed source surface and a fixed target (the
// dist_V^2 of eqs. 4.5 and 4.7), with its gradient with respect to the source vertices.
#pragma once
#include <Eigen/Core>

namespace bcassim {

class SurfaceDistance {
 public:
  virtual ~SurfaceDistance() = default;
  // Squared distance from the surface (V: #V by 3, F: #F by 3) to the target.
  virtual double value(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) const = 0;
  // Same; grad receives d/dV (#V by 3, resized).
  virtual double valueAndGradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                  Eigen::MatrixX3d* grad) const = 0;
};

}  // namespace bcassim
