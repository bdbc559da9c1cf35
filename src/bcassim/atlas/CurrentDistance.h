// Current distance (the oriented variant of eq. 4.5): Gaussian in position times n_i . m_j;
// sensitive to face orientation, cheaper and convex in the normals.
#pragma once
#include "bcassim/atlas/FaceKernelDistance.h"

namespace bcassim {

class CurrentDistance : public FaceKernelDistance {
 public:
  CurrentDistance(const TriMesh& target, double sigmaW)
      : FaceKernelDistance(target, sigmaW, FaceKernelKind::Current) {}
};

}  // namespace bcassim
