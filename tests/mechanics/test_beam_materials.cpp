// Thesis §2.1.5 (Fig. 2.6): bending a 15 x 3 x 3 cm beam, the nonlinear models (StVK, Neo-Hookean,
// Mooney-Rivlin) stay within 5 % of the corotational one while the linear model is off by more
// than 50 % (it cannot rotate). Small variant of examples/beam-materials (13,824 tets).
#include <gtest/gtest.h>

#include "FemTestHelpers.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {
namespace {
using testing::nodesWhere;

Eigen::VectorXd bentBeamDisplacement(const std::shared_ptr<const TetMesh>& mesh,
                                     const Material& material) {
  MechanicalModel model = makeMechanicalModel(mesh, {material}, 1000.0, MassKind::Lumped);
  model.dirichlet = DirichletConditions(
      {{nodesWhere(*mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
  const auto bottom = nodesWhere(*mesh, [](const Vec3& p) { return p.z() < 1e-12; });
  model.loads.push_back({bottom, Vec3(0, 0, -50.0 / bottom.size()), {}});  // 50 N in all
  Eigen::VectorXd x = model.restPositions();
  StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-9, 60, 4});
  EXPECT_TRUE(solver.solve(model, 0.0, x).converged) << materialName(material);
  return x - model.restPositions();
}

// max_i |u_i - ref_i| / max_i |ref_i| over the nodes.
double relativeDifference(const Eigen::VectorXd& u, const Eigen::VectorXd& ref) {
  double diff = 0, scale = 0;
  for (Eigen::Index i = 0; i < u.size() / 3; ++i) {
    diff = std::max(diff, (u.segment<3>(3 * i) - ref.segment<3>(3 * i)).norm());
    scale = std::max(scale, ref.segment<3>(3 * i).norm());
  }
  return diff / scale;
}

TEST(BeamMaterials, NonlinearModelsAgreeAndLinearIsFarOff) {
  // Thesis parameters: E = 1.542 MPa, nu = 0.49; Neo-Hookean mu = 0.5174 MPa (mu/2 = 0.2587 MPa);
  // Mooney-Rivlin c10 = 0.2112 MPa, c01 = 0.0617 MPa.
  const double E = 1.542e6, nu = 0.49;
  const auto lame = LameParameters::fromYoungPoisson(E, nu);
  auto mesh = std::make_shared<const TetMesh>(makeBoxMesh(Vec3(0.15, 0.03, 0.03), 36, 8, 8));
  const Eigen::VectorXd corotational =
      bentBeamDisplacement(mesh, makeMaterial("corotational", E, nu));
  const double stvk =
      relativeDifference(bentBeamDisplacement(mesh, makeMaterial("stvk", E, nu)), corotational);
  const double neoHookean = relativeDifference(
      bentBeamDisplacement(mesh, NeoHookeanMaterial{lame.lambda, 0.5174e6}), corotational);
  const double mooneyRivlin = relativeDifference(
      bentBeamDisplacement(mesh, MooneyRivlinMaterial{0.2112e6, 0.0617e6, E / (3 * (1 - 2 * nu))}),
      corotational);
  const double linear =
      relativeDifference(bentBeamDisplacement(mesh, makeMaterial("linear", E, nu)), corotational);
  EXPECT_LT(stvk, 0.05);
  EXPECT_LT(neoHookean, 0.05);
  EXPECT_LT(mooneyRivlin, 0.05);
  EXPECT_GT(linear, 0.50);
  std::printf(
      "relative to corotational: StVK %.1f %%, Neo-Hookean %.1f %%, Mooney-Rivlin %.1f %%, "
      "linear %.1f %%\n",
      100 * stvk, 100 * neoHookean, 100 * mooneyRivlin, 100 * linear);
}

}  // namespace
}  // namespace bcassim
