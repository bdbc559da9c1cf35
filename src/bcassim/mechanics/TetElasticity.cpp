#include "bcassim/mechanics/TetElasticity.h"

#include <fmt/format.h>

#include "bcassim/Error.h"
#include "bcassim/mechanics/ElementKernels.h"

namespace bcassim {
namespace {

// Deformation gradient F = sum_a x_a (grad N_a)^T of tet t (eq. 2.7).
inline Mat3 deformationGradient(const Eigen::VectorXd& x, const Eigen::Vector4i& tet,
                                const Eigen::Matrix<double, 4, 3>& gradN) {
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < 4; ++a) F.noalias() += x.segment<3>(3 * tet(a)) * gradN.row(a);
  return F;
}

}  // namespace

TetElasticity::TetElasticity(const TetMesh& mesh, std::vector<Material> regionMaterials)
    : T_(mesh.T), materials_(std::move(regionMaterials)) {
  if (materials_.empty()) throw InputError("elasticity: no material given");
  const Eigen::Index nt = mesh.numTets();
  gradN_.resize(nt);
  volume_.resize(nt);
  tetsOfRegion_.resize(materials_.size());
  for (Eigen::Index t = 0; t < nt; ++t) {
    Mat3 Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = (mesh.V.row(T_(t, k + 1)) - mesh.V.row(T_(t, 0))).transpose();
    const double det = Dm.determinant();
    if (!(det > 0))
      throw InputError(fmt::format("elasticity: tet {} has non-positive rest volume {:.3g} m^3", t,
                                   det / 6.0));
    volume_[t] = det / 6.0;
    const Mat3 DmInv = Dm.inverse();
    // grad N_{1..3} are the rows of Dm^-1; grad N_0 = -(sum of the others).
    gradN_[t].block<3, 3>(1, 0) = DmInv;
    gradN_[t].row(0) = -DmInv.colwise().sum();
    const int r = materials_.size() == 1 ? 0 : mesh.regionOf(t);
    if (r < 0 || r >= static_cast<int>(materials_.size()))
      throw InputError(fmt::format("elasticity: tet {} is in region {} but {} region materials are "
                                   "defined",
                                   t, r, materials_.size()));
    tetsOfRegion_[r].push_back(static_cast<int>(t));
  }
}

// Calls visit(material, tets) once per region with the concrete material type, so the per-tet
// loops inside are compiled for each material without dispatch in the hot path.
template <class Visitor>
void TetElasticity::forEachRegion(Visitor&& visit) const {
  for (size_t r = 0; r < materials_.size(); ++r)
    std::visit([&](const auto& m) { visit(m, tetsOfRegion_[r]); }, materials_[r]);
}

double TetElasticity::energy(const Eigen::VectorXd& x) const {
  double W = 0.0;
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    for (int t : tets) {
      const Eigen::Vector4i tet = T_.row(t);
      W += volume_[t] * material.energy(deformationGradient(x, tet, gradN_[t]));
    }
  });
  return W;
}

Eigen::Index TetElasticity::countInverted(const Eigen::VectorXd& x) const {
  Eigen::Index inverted = 0;
  for (Eigen::Index t = 0; t < T_.rows(); ++t) {
    const Eigen::Vector4i tet = T_.row(t);
    if (deformationGradient(x, tet, gradN_[t]).determinant() <= 0) ++inverted;
  }
  return inverted;
}

void TetElasticity::addInternalForces(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  Eigen::Index inverted = 0;
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    for (int t : tets) {
      const Eigen::Vector4i tet = T_.row(t);
      const Mat3 F = deformationGradient(x, tet, gradN_[t]);
      if (F.determinant() <= 0) ++inverted;
      const Eigen::Matrix<double, 3, 4> H = volume_[t] * material.pk1(F) * gradN_[t].transpose();
      for (int a = 0; a < 4; ++a) f.segment<3>(3 * tet(a)) += H.col(a);
    }
  });
  inverted_ = inverted;
}

void TetElasticity::addForcesAndStiffness(const Eigen::VectorXd& x, const AssemblyPattern& pattern,
                                          double scale, Eigen::VectorXd& f, SparseMatrix& K) const {
  Eigen::Index inverted = 0;
  double* values = K.valuePtr();
  forEachRegion([&](const auto& material, const std::vector<int>& tets) {
    for (int t : tets) {
      const Eigen::Vector4i tet = T_.row(t);
      const auto& G = gradN_[t];
      const Mat3 F = deformationGradient(x, tet, G);
      if (F.determinant() <= 0) ++inverted;
      ElementForces H;
      Mat12 Ke;
      elementForcesAndStiffness(material, F, G, volume_[t], H, Ke);
      for (int a = 0; a < 4; ++a) f.segment<3>(3 * tet(a)) += H.col(a);
      if (scale != 1.0) Ke *= scale;
      const int* slot = pattern.tetSlots(t);
      for (int r = 0; r < 12; ++r)
        for (int c = 0; c < 12; ++c) values[slot[12 * r + c]] += Ke(r, c);
    }
  });
  inverted_ = inverted;
}

}  // namespace bcassim
