// Multi-object data term of a registration: the surfaces' kernel distance plus, for a curve
// drawn on both (the liver's ridge, .eseg label 3), the curves' own varifold distance, so that
// the deformation matches the labelled landmarks as well as the shape.
#pragma once
#include <Eigen/Core>
#include <memory>

#include "bcassim/atlas/CurveKernelDistance.h"
#include "bcassim/atlas/FaceKernelDistance.h"
#include "bcassim/atlas/Registration.h"
#include "bcassim/atlas/SurfaceDistance.h"

namespace bcassim {

class MultiObjectDistance : public SurfaceDistance {
 public:
  // D(V) = D_surface(V) + w D_curve(V), w = curveWeight <T,T>_surface / <T,T>_curve: each
  // object's distance relative to its own size, so that curveWeight = 1 weighs a curve as much as
  // the surface whatever their units (m^2 against m) and sampling.
  MultiObjectDistance(const TriMesh& target, const Eigen::MatrixX2i& targetCurve,
                      const Eigen::MatrixX2i& sourceCurve, double sigmaW, FaceKernelKind kind,
                      double curveWeight);

  double value(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) const override;
  double valueAndGradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                          Eigen::MatrixX3d* grad) const override;

  double curveWeight() const { return weight_; }  // w above

 private:
  FaceKernelDistance surface_;
  CurveKernelDistance curve_;
  double weight_;
};

// The data term a registration onto `target` uses: the surfaces alone, or with the curve term
// when `curves` is given and both of its curves have edges (options.curveWeight > 0).
std::unique_ptr<SurfaceDistance> makeDataTerm(const TriMesh& target,
                                              const RegistrationOptions& options,
                                              const CurvePair* curves);

}  // namespace bcassim
