// Varifold distance (eq. 4.5 for curves) between curves drawn on surfaces, given as edges: a
// moving source curve (vertex pairs of the surface being deformed) and a fixed target one.
#pragma once
#include <Eigen/Core>

#include "bcassim/atlas/OrientedFaces.h"

namespace bcassim {

// Segments as oriented points: centre c = edge midpoint, n = v1 - v0 (|n| = length), so that the
// face kernels of FaceKernelSum.h apply unchanged (the varifold's (n.m)^2 / (|n||m|) ignores
// which way an edge was walked). Throws InputError on an index out of range.
OrientedFaces orientedSegments(const Eigen::MatrixX3d& V, const Eigen::MatrixX2i& E);

class CurveKernelDistance {
 public:
  // targetV, targetEdges: the fixed curve; sourceEdges: vertex pairs into the V that value()
  // receives. sigmaW: kernel width (m), > 0. Throws InputError on bad input or an empty curve.
  CurveKernelDistance(const Eigen::MatrixX3d& targetV, const Eigen::MatrixX2i& targetEdges,
                      Eigen::MatrixX2i sourceEdges, double sigmaW);

  double value(const Eigen::MatrixX3d& V) const;
  // Adds d/dV of the value to *grad (#V by 3, already sized).
  double addValueAndGradient(const Eigen::MatrixX3d& V, Eigen::MatrixX3d* grad) const;

  double targetSquaredNorm() const { return targetNorm2_; }  // <T, T> (m)

 private:
  OrientedFaces target_;
  Eigen::MatrixX2i source_;
  double sigma_;
  double targetNorm2_;
};

}  // namespace bcassim
