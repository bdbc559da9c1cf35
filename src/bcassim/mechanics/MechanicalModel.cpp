#include "bcassim/mechanics/MechanicalModel.h"

namespace bcassim {

MechanicalModel makeMechanicalModel(std::shared_ptr<const TetMesh> mesh,
                                    std::vector<Material> regionMaterials, double density,
                                    MassKind massKind, int meanDilatationPatchTets) {
  TetElasticity elasticity(*mesh, std::move(regionMaterials), meanDilatationPatchTets);
  auto pattern = std::make_shared<const AssemblyPattern>(*mesh, elasticity.patchNodeSets());
  MassMatrix mass(*mesh, *pattern, density, massKind);
  MechanicalModel model{
      std::move(mesh), std::move(pattern), std::move(elasticity), std::move(mass), {}, {}, {}, {}};
  return model;
}

Eigen::VectorXd MechanicalModel::restPositions() const {
  Eigen::MatrixX3d Vt = mesh->V;
  Eigen::VectorXd x(3 * Vt.rows());
  for (Eigen::Index i = 0; i < Vt.rows(); ++i) x.segment<3>(3 * i) = Vt.row(i).transpose();
  return x;
}

MechanicalState MechanicalModel::restState() const {
  MechanicalState s{restPositions(), Eigen::VectorXd::Zero(3 * mesh->numNodes()), 0.0};
  dirichlet.impose(restPositions(), 0.0, s.x);
  return s;
}

void MechanicalModel::externalForces(double t, Eigen::VectorXd& f) const {
  f.setZero(3 * mesh->numNodes());
  for (const NodalLoad& load : loads) load.addTo(t, f);
  if (!gravity.isZero()) {
    const Eigen::VectorXd& m = mass.lumpedDiagonal();
    for (Eigen::Index i = 0; i < mesh->numNodes(); ++i)
      f.segment<3>(3 * i) += m.segment<3>(3 * i).cwiseProduct(gravity);
  }
}

void MechanicalModel::internalForces(double t, const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  f.setZero(x.size());
  elasticity.addInternalForces(x, f);
  springs.addInternalForces(*mesh, x, t, f);
  for (const ControlPointSet& c : controls) c.addInternalForces(*mesh, x, t, f);
}

void MechanicalModel::internalForces(double t, const Eigen::VectorXd& x, Eigen::VectorXd& f,
                                     ChunkedForces& chunks) const {
  f.setZero(x.size());
  elasticity.addInternalForces(x, f, chunks);
  springs.addInternalForces(*mesh, x, t, f);
  for (const ControlPointSet& c : controls) c.addInternalForces(*mesh, x, t, f);
}

void MechanicalModel::internalForcesAndStiffness(double t, const Eigen::VectorXd& x,
                                                 Eigen::VectorXd& f, SparseMatrix& K) const {
  f.setZero(x.size());
  if (K.nonZeros() != pattern->emptyMatrix().nonZeros())
    K = pattern->emptyMatrix();
  else
    K.coeffs().setZero();
  elasticity.addForcesAndStiffness(x, *pattern, 1.0, f, K);
  springs.addForcesAndStiffness(*mesh, x, t, *pattern, 1.0, f, K);
  for (const ControlPointSet& c : controls)
    c.addForcesAndStiffness(*mesh, x, t, *pattern, 1.0, f, K);
}

double MechanicalModel::storedEnergy(double t, const Eigen::VectorXd& x) const {
  double W = elasticity.energy(x) + springs.energy(*mesh, x, t);
  for (const ControlPointSet& c : controls) W += c.energy(*mesh, x, t);
  return W;
}

}  // namespace bcassim
