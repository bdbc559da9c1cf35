#include "bcassim/mechanics/DirichletConditions.h"

#include <algorithm>
#include <map>

namespace bcassim {

DirichletConditions::DirichletConditions(std::vector<DirichletRegion> regions,
                                         const AssemblyPattern& pattern)
    : regions_(std::move(regions)) {
  std::map<int, int> regionOf;
  for (size_t r = 0; r < regions_.size(); ++r)
    for (int n : regions_[r].nodes)
      for (int i = 0; i < 3; ++i)
        if (regions_[r].components[i]) regionOf[3 * n + i] = static_cast<int>(r);
  for (auto [dof, r] : regionOf) {
    dofs_.push_back(dof);
    regionOfDof_.push_back(r);
  }
  const SparseMatrix& A = pattern.emptyMatrix();
  isConstrained_.assign(A.rows(), 0);
  for (int d : dofs_) isConstrained_[d] = 1;
  for (Eigen::Index c = 0; c < A.outerSize(); ++c)
    for (int k = A.outerIndexPtr()[c]; k < A.outerIndexPtr()[c + 1]; ++k)
      if (isConstrained_[c] || isConstrained_[A.innerIndexPtr()[k]]) slotsToZero_.push_back(k);
  for (int d : dofs_) diagonalSlots_.push_back(pattern.diagonalSlot(d));
}

Eigen::VectorXd DirichletConditions::targetPositions(const Eigen::VectorXd& rest, double t) const {
  Eigen::VectorXd target(dofs_.size());
  for (size_t k = 0; k < dofs_.size(); ++k) {
    const DirichletRegion& r = regions_[regionOfDof_[k]];
    target(k) = rest(dofs_[k]) + r.displacement(dofs_[k] % 3) * r.profile.value(t);
  }
  return target;
}

void DirichletConditions::impose(const Eigen::VectorXd& rest, double t, Eigen::VectorXd& x) const {
  const Eigen::VectorXd target = targetPositions(rest, t);
  for (size_t k = 0; k < dofs_.size(); ++k) x(dofs_[k]) = target(k);
}

void DirichletConditions::eliminate(SparseMatrix& A, Eigen::VectorXd& b,
                                    const Eigen::VectorXd& known) const {
  eliminateRightHandSide(A, b, known);
  eliminateMatrix(A);
}

void DirichletConditions::eliminateRightHandSide(const SparseMatrix& A, Eigen::VectorXd& b,
                                                 const Eigen::VectorXd& known) const {
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* values = A.valuePtr();
  for (size_t k = 0; k < dofs_.size(); ++k) {
    if (known(k) == 0.0) continue;
    const int c = dofs_[k];
    for (int s = outer[c]; s < outer[c + 1]; ++s) b(inner[s]) -= values[s] * known(k);
  }
  for (size_t k = 0; k < dofs_.size(); ++k) b(dofs_[k]) = known(k);
}

void DirichletConditions::eliminateMatrix(SparseMatrix& A) const {
  double* values = A.valuePtr();
  for (int s : slotsToZero_) values[s] = 0.0;
  for (size_t k = 0; k < dofs_.size(); ++k) values[diagonalSlots_[k]] = 1.0;
}

}  // namespace bcassim
