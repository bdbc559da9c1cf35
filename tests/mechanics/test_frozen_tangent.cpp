// The linearly implicit Euler step with a given tangent (ImplicitEuler::stepWithTangent, a
// one-stage Rosenbrock-W step): with the state's own tangent it is eq. 2.16 exactly, Dirichlet
// motion included; with the tangent of another state its one-step difference from eq. 2.16 is
// O(dt^2) (first-order consistency for any tangent); springs with other coefficients than the
// tangent's are still exact; a wrong dt is refused.
#include <gtest/gtest.h>

#include <cmath>

#include "FemTestHelpers.h"
#include "bcassim/Error.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

// A 300-node StVK cylinder: one end fixed, the other end pushed sideways (prescribed motion), a
// sine load at mid-length, mass damping; `stiffnessDamping` s of Rayleigh stiffness damping.
MechanicalModel cylinder(double stiffnessDamping) {
  auto mesh = std::make_shared<const TetMesh>(makeCylinderMesh(0.015, 0.18, 300));
  MechanicalModel model =
      makeMechanicalModel(mesh, {makeMaterial("stvk", 8000, 0.45)}, 1000, MassKind::Lumped);
  const auto [base, tip, middle] = testing::cylinderNodes(*mesh, 0.015, 0.18);
  model.dirichlet = DirichletConditions(
      {{base}, {tip, Vec3(0.01, 0, 0), {TimeProfile::Kind::Sine, 1.0}}}, *model.pattern);
  model.loads.push_back({middle, Vec3(0, 0.05 / middle.size(), 0), {TimeProfile::Kind::Sine, 0.7}});
  model.rayleighMass = 0.1;
  model.rayleighStiffness = stiffnessDamping;
  return model;
}

// The state after `steps` exact steps of dt: deformed and moving.
MechanicalState movingState(const MechanicalModel& model, int steps, double dt) {
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), {dt, 0, 1e-10});
  MechanicalState s = model.restState();
  for (int i = 0; i < steps; ++i) euler.step(model, s);
  return s;
}

TEST(FrozenTangent, OwnTangentGivesTheImplicitEulerStep) {
  const MechanicalModel model = cylinder(0.01);
  const double dt = 0.01;
  MechanicalState s = movingState(model, 20, dt);
  ASSERT_GT(s.v.norm(), 1e-3);
  MechanicalState exact = s, frozen = s;
  ImplicitEuler a(model, makeLinearSolver("cholmod"), {dt, 0, 1e-10});
  ImplicitEuler b(model, makeLinearSolver("cholmod"), {dt, 0, 1e-10});
  a.step(model, exact);
  b.stepWithTangent(model, frozen, *FrozenTangent::build(model, s, dt));
  EXPECT_LT((frozen.v - exact.v).norm(), 1e-10 * exact.v.norm());
  EXPECT_LT((frozen.x - exact.x).norm(), 1e-12 * exact.x.norm());
  EXPECT_DOUBLE_EQ(frozen.t, exact.t);
  // The pushed tip reaches its prescribed position exactly.
  const Eigen::VectorXd target = model.dirichlet.targetPositions(model.restPositions(), frozen.t);
  for (Eigen::Index k = 0; k < target.size(); ++k)
    EXPECT_NEAR(frozen.x(model.dirichlet.constrainedDofs()[k]), target(k), 1e-14);
}

TEST(FrozenTangent, TangentOfAnotherStateIsFirstOrderConsistent) {
  // Without stiffness damping the one-step velocity difference to eq. 2.16 is
  // -dt^2 M^-1 (K - K_frozen) v + O(dt^3): halving dt divides it by 4.
  const MechanicalModel model = cylinder(0.0);
  const MechanicalState s = movingState(model, 30, 0.01);
  MechanicalState other = s;
  other.x += 0.2 * (movingState(model, 25, 0.01).x - s.x);  // another deformation, mm apart
  std::vector<double> differences;
  for (double dt : {2e-4, 1e-4, 5e-5, 2.5e-5}) {
    MechanicalState exact = s, frozen = s;
    ImplicitEuler a(model, makeLinearSolver("cholmod"), {dt, 0, 1e-10});
    a.step(model, exact);
    a.stepWithTangent(model, frozen, *FrozenTangent::build(model, other, dt));
    differences.push_back((frozen.v - exact.v).norm());
  }
  for (size_t i = 1; i < differences.size(); ++i) {
    const double order = std::log2(differences[i - 1] / differences[i]);
    EXPECT_NEAR(order, 2.0, 0.15) << "dt halving " << i << ": " << differences[i - 1] << " -> "
                                  << differences[i];
  }
}

// Springs are what the estimated parameters change: a tangent built with other spring
// coefficients (and the same state) must still give eq. 2.16 exactly, since the springs' own
// stiffness replaces the tangent's through the low-rank correction.
TEST(FrozenTangent, SpringsOfTheStepReplaceTheTangentsExactly) {
  MechanicalModel model = cylinder(0.01);
  std::vector<CubicSpring> springs;
  for (int tet = 0; tet < model.mesh->numTets(); ++tet) {
    const Vec3 centre =
        0.25 *
        (model.mesh->V.row(model.mesh->T(tet, 0)) + model.mesh->V.row(model.mesh->T(tet, 1)) +
         model.mesh->V.row(model.mesh->T(tet, 2)) + model.mesh->V.row(model.mesh->T(tet, 3)))
            .transpose();
    if (std::abs(centre.z() - 0.12) > 0.01 || centre.y() < 0.008) continue;
    springs.push_back({tet, Vec4::Constant(0.25), centre + Vec3(0, 0.03, 0.01), 0.025,
                       static_cast<int>(springs.size() % 2)});
  }
  ASSERT_GE(springs.size(), 4u);
  ASSERT_LE(springs.size(), static_cast<size_t>(FrozenTangent::kMaxCorrectedSprings));
  model.springs = CubicSpringSet(springs, {{2e5, 0, 5.0}, {1e5, 0, 2.0}});
  const double dt = 0.01;
  const MechanicalState s = movingState(model, 20, dt);

  MechanicalModel softer = model;  // the mean's coefficients: 10x softer
  softer.springs.setCoefficients(0, {2e4, 0, 0.5});
  softer.springs.setCoefficients(1, {1e4, 0, 0.2});
  const auto tangent = FrozenTangent::build(softer, s, dt);
  ASSERT_TRUE(tangent->correctsSprings());
  MechanicalState exact = s, frozen = s;
  ImplicitEuler a(model, makeLinearSolver("cholmod"), {dt, 0, 1e-10});
  a.step(model, exact);
  a.stepWithTangent(model, frozen, *tangent);
  ASSERT_GT((exact.v - s.v).norm(), 1e-4);
  EXPECT_LT((frozen.v - exact.v).norm(), 1e-9 * (exact.v - s.v).norm());
  EXPECT_LT((frozen.x - exact.x).norm(), 1e-12 * exact.x.norm());
}

TEST(FrozenTangent, TangentBuiltForAnotherTimeStepIsRefused) {
  const MechanicalModel model = cylinder(0.01);
  MechanicalState s = model.restState();
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), {0.01, 0, 1e-10});
  try {
    euler.stepWithTangent(model, s, *FrozenTangent::build(model, s, 0.02));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "implicit Euler: the shared tangent was built for dt = 0.02 s, this integrator "
                 "steps 0.01 s");
  }
}

}  // namespace
}  // namespace bcassim
