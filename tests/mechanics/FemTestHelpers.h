// Small helpers shared by the FEM tests: node selection by coordinate and model construction.
#pragma once
#include <cmath>
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

// The nodes of a makeCylinderMesh(radius, length, n) cylinder along z that the tests hold or
// load: its base (z = 0), its tip (z = length) and a patch on the +y side of its middle
// (|z - length / 2| < 1 cm, y > 0.8 radius).
struct CylinderNodes {
  std::vector<int> base, tip, middle;
};
inline CylinderNodes cylinderNodes(const TetMesh& mesh, double radius, double length) {
  CylinderNodes out;
  for (int i = 0; i < mesh.numNodes(); ++i) {
    if (mesh.V(i, 2) < 1e-9) out.base.push_back(i);
    if (mesh.V(i, 2) > length - 1e-9) out.tip.push_back(i);
    if (std::abs(mesh.V(i, 2) - 0.5 * length) < 0.01 && mesh.V(i, 1) > 0.8 * radius)
      out.middle.push_back(i);
  }
  return out;
}

}  // namespace bcassim::testing
