#include "bcassim/mechanics/MassMatrix.h"

#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {

MassMatrix::MassMatrix(const TetMesh& mesh, const AssemblyPattern& pattern, double density,
                       MassKind kind)
    : kind_(kind), lumped_(Eigen::VectorXd::Zero(3 * mesh.numNodes())) {
  if (kind == MassKind::Consistent) consistent_ = pattern.emptyMatrix();
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const double m = density * signedVolume(mesh, t);
    totalMass_ += m;
    for (int a = 0; a < 4; ++a) lumped_.segment<3>(3 * mesh.T(t, a)).array() += m / 4.0;
    if (kind == MassKind::Consistent) {
      const int* slot = pattern.tetSlots(t);
      double* values = consistent_.valuePtr();
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          for (int i = 0; i < 3; ++i)
            values[slot[(3 * a + i) * 12 + 3 * b + i]] += m / 20.0 * (a == b ? 2.0 : 1.0);
    }
  }
}

void MassMatrix::multiply(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
  if (kind_ == MassKind::Lumped)
    out = lumped_.cwiseProduct(v);
  else
    out.noalias() = consistent_ * v;
}

void MassMatrix::addTo(const AssemblyPattern& pattern, double scale, SparseMatrix& A) const {
  double* values = A.valuePtr();
  if (kind_ == MassKind::Lumped) {
    for (Eigen::Index d = 0; d < lumped_.size(); ++d)
      values[pattern.diagonalSlot(d)] += scale * lumped_(d);
  } else {
    const double* m = consistent_.valuePtr();
    for (Eigen::Index k = 0; k < consistent_.nonZeros(); ++k) values[k] += scale * m[k];
  }
}

double MassMatrix::kineticEnergy(const Eigen::VectorXd& v) const {
  if (kind_ == MassKind::Lumped) return 0.5 * v.dot(lumped_.cwiseProduct(v));
  return 0.5 * v.dot(consistent_ * v);
}

}  // namespace bcassim
