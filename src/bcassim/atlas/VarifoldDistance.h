// Varifold distance of thesis eq. 4.5: Gaussian in position times the squared cosine of the
// normals, weighted by areas; blind to face orientation.
#pragma once
#include "bcassim/atlas/FaceKernelDistance.h"

namespace bcassim {

class VarifoldDistance : public FaceKernelDistance {
 public:
  VarifoldDistance(const TriMesh& target, double sigmaW)
      : FaceKernelDistance(target, sigmaW, FaceKernelKind::Varifold) {}
};

}  // namespace bcassim
