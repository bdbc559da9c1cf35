// Small helpers shared by the FEM tests: node selection by coordinate and model construction.
#pragma once
#include <functional>
#include <memory>

#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim::testing {

inline std::vector<int> nodesWhere(const TetMesh& mesh, const std::function<bool(const Vec3&)>& p) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    if (p(mesh.V.row(i).transpose())) out.push_back(static_cast<int>(i));
  return out;
}

inline MechanicalModel boxModel(const Vec3& size, int nx, int ny, int nz, const Material& material,
                                double density = 1000.0, MassKind mass = MassKind::Lumped) {
  auto mesh = std::make_shared<const TetMesh>(makeBoxMesh(size, nx, ny, nz));
  return makeMechanicalModel(mesh, {material}, density, mass);
}

}  // namespace bcassim::testing
