// The FEM adapter of the filters: a forecast is exactly one implicit-Euler step of the model with
// the given state and parameters, and sharing worker 0's factorisation changes nothing beyond
// the PCG tolerance (thesis Alg. 4/5).
#include <gtest/gtest.h>

#include "bcassim/app/MechanicalForecastModel.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

MechanicalModel cylinderModel() {
  auto mesh = std::make_shared<const TetMesh>(makeCylinderMesh(0.015, 0.18, 300));
  MechanicalModel model = makeMechanicalModel(mesh, {makeMaterial("stvk", 8000, 0.45)}, 1000,
                                              MassKind::Lumped);
  std::vector<int> ends, middle;
  for (int i = 0; i < mesh->numNodes(); ++i) {
    if (mesh->V(i, 2) < 1e-9 || mesh->V(i, 2) > 0.18 - 1e-9) ends.push_back(i);
    if (std::abs(mesh->V(i, 2) - 0.09) < 0.01 && mesh->V(i, 1) > 0.012) middle.push_back(i);
  }
  model.dirichlet = DirichletConditions({{ends}}, *model.pattern);
  model.loads.push_back({middle, Vec3(0, 0.02 / middle.size(), 0), {TimeProfile::Kind::Sine, 1.0}});
  model.rayleighMass = 0.1;
  return model;
}

TEST(MechanicalForecastModel, ForecastIsOneImplicitEulerStepWithTheGivenParameters) {
  MechanicalModel model = cylinderModel();
  const MechanicalState initial = model.restState();
  const std::vector<MappedPoint> observed = mapPoints(*model.mesh, model.mesh->V.topRows(5));
  ForecastModelOptions options;
  options.solver = "cholmod";
  MechanicalForecastModel adapter(model, {0.01, 0, 1e-10}, observed, {YoungModulusTarget{0, "stvk", 0.45}},
                                  initial, options, 0, nullptr);
  EXPECT_EQ(adapter.stateSize(), 6 * model.mesh->numNodes());
  EXPECT_EQ(adapter.observationSize(), 15);

  Eigen::VectorXd newState, predicted;
  adapter.forecast(adapter.packState(initial), Eigen::VectorXd::Constant(1, 6000.0), newState,
                   predicted);

  MechanicalModel direct = model;
  direct.elasticity.setMaterial(0, makeMaterial("stvk", 6000, 0.45));
  ImplicitEuler euler(direct, makeLinearSolver("cholmod"), {0.01, 0, 1e-10});
  MechanicalState s = initial;
  euler.step(direct, s);
  const Eigen::Index n = s.x.size();
  EXPECT_LT((newState.head(n) - s.x).norm(), 1e-12 * s.x.norm());
  EXPECT_LT((newState.tail(n) - s.v).norm(), 1e-9 * std::max(s.v.norm(), 1e-12));
  for (int i = 0; i < 5; ++i)
    EXPECT_LT((predicted.segment<3>(3 * i) - interpolate(observed[i], *model.mesh, s.x)).norm(), 1e-14);
  // The reference only moves on endStep.
  EXPECT_EQ(adapter.reference().t, 0.0);
  adapter.endStep(newState, Eigen::VectorXd::Constant(1, 6000.0));
  EXPECT_NEAR(adapter.reference().t, 0.01, 1e-15);
  EXPECT_NEAR(readParameter(YoungModulusTarget{0, "stvk", 0.45}, adapter.model()), 6000.0, 1e-9);
}

TEST(MechanicalForecastModel, SharedFactorisationGivesTheDirectResult) {
  MechanicalModel model = cylinderModel();
  const MechanicalState initial = model.restState();
  for (bool withinStep : {true, false}) {
  auto shared = std::make_shared<SharedFactorization>();
  shared->withinStep = withinStep;
  ForecastModelOptions reuse;  // factorized-pcg, shared
  reuse.refresh.relTol = 1e-12;
  ForecastModelOptions direct;
  direct.solver = "cholmod";
  direct.shareFactorization = false;
  const std::vector<ModelParameterTarget> params{YoungModulusTarget{0, "stvk", 0.45}};
  MechanicalForecastModel w0(model, {0.01, 0, 1e-10}, {}, params, initial, reuse, 0, shared);
  MechanicalForecastModel w1(model, {0.01, 0, 1e-10}, {}, params, initial, reuse, 1, shared);
  MechanicalForecastModel ref(model, {0.01, 0, 1e-10}, {}, params, initial, direct, 0, nullptr);
  Eigen::VectorXd state = w0.packState(initial), a, b, c, p;
  for (int step = 0; step < 20; ++step) {
    const Eigen::VectorXd E0 = Eigen::VectorXd::Constant(1, 8000.0);
    const Eigen::VectorXd E1 = Eigen::VectorXd::Constant(1, 9000.0);
    w0.forecast(state, E0, a, p);  // publishes its factorisation, for now or for the next step
    if (withinStep || step > 0) ASSERT_TRUE(shared->factor);
    w1.forecast(state, E1, b, p);  // preconditioned by worker 0's factor of another E
    ref.forecast(state, E1, c, p);
    EXPECT_LT((b - c).norm(), 1e-8 * c.norm()) << "step " << step;
    for (auto* w : {&w0, &w1, &ref}) w->endStep(a, E0);
    state = a;
  }
  }
}

}  // namespace
}  // namespace bcassim
