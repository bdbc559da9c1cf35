// Kernel distance of eq. 4.5 between triangle meshes: |S - T|^2 = <S,S> + <T,T> - 2 <S,T>, with
// the pair kernel of FaceKernelSum.h (varifold or current); <T,T> is computed once.
#pragma once
#include "bcassim/atlas/FaceKernelSum.h"
#include "bcassim/atlas/OrientedFaces.h"
#include "bcassim/atlas/SurfaceDistance.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

class FaceKernelDistance : public SurfaceDistance {
 public:
  // sigmaW: width of the Gaussian in position (m), > 0. Throws InputError on bad input.
  FaceKernelDistance(const TriMesh& target, double sigmaW, FaceKernelKind kind);

  double value(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) const override;
  double valueAndGradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                          Eigen::MatrixX3d* grad) const override;

  double sigma() const { return sigma_; }
  FaceKernelKind kind() const { return kind_; }
  double targetSquaredNorm() const { return targetNorm2_; }  // <T, T>

 private:
  OrientedFaces target_;
  double sigma_;
  FaceKernelKind kind_;
  double targetNorm2_;
};

}  // namespace bcassim
