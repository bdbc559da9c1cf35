// The FEM adapter of the filters: a forecast is exactly one implicit-Euler step of the model with
// the given state and parameters, and sharing worker 0's factorisation changes nothing beyond
// the PCG tolerance (thesis Alg. 4/5).
#include <gtest/gtest.h>

#include "bcassim/coupling/MechanicalForecastModel.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

MechanicalModel cylinderModel() {
  auto mesh = std::make_shared<const TetMesh>(makeCylinderMesh(0.015, 0.18, 300));
  MechanicalModel model =
      makeMechanicalModel(mesh, {makeMaterial("stvk", 8000, 0.45)}, 1000, MassKind::Lumped);
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
  MechanicalForecastModel adapter(model, {0.01, 0, 1e-10}, observed,
                                  {YoungModulusTarget{0, "stvk", 0.45}}, initial, options, 0,
                                  nullptr);
  EXPECT_EQ(adapter.stateSize(), 6 * model.mesh->numNodes());
  EXPECT_EQ(adapter.observableSize(), 15);

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
    EXPECT_LT((predicted.segment<3>(3 * i) - interpolate(observed[i], *model.mesh, s.x)).norm(),
              1e-14);
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
      if (withinStep || step > 0) {
        ASSERT_TRUE(shared->factor);
      }
      w1.forecast(state, E1, b, p);  // preconditioned by worker 0's factor of another E
      ref.forecast(state, E1, c, p);
      EXPECT_LT((b - c).norm(), 1e-8 * c.norm()) << "step " << step;
      for (auto* w : {&w0, &w1, &ref}) w->endStep(a, E0);
      state = a;
    }
  }
}

// tangent: mean — every worker steps with the tangent worker 0 built at the analysed mean (with
// the mean's parameters): synchronously at endStep every N steps (N = tangentRefreshEvery), or in
// the background, launched when due and adopted B steps later (B = tangentBackgroundSteps).
TEST(MechanicalForecastModel, MeanTangentForecastsStepWithTheMeansTangent) {
  const MechanicalModel model = cylinderModel();
  const MechanicalState initial = model.restState();
  const std::vector<ModelParameterTarget> params{YoungModulusTarget{0, "stvk", 0.45}};
  const ImplicitEulerOptions euler{0.01, 0, 1e-10};
  const Eigen::VectorXd E0 = Eigen::VectorXd::Constant(1, 8000.0);
  const Eigen::VectorXd E1 = Eigen::VectorXd::Constant(1, 9500.0);
  MechanicalModel at8000 = model, at9500 = model;
  applyParameter(params[0], 8000.0, at8000);
  applyParameter(params[0], 9500.0, at9500);

  struct Schedule {
    bool background;
    int every, steps;  // steps 0: the default (1 for dynamic steps)
  };
  constexpr int kSteps = 6;
  for (const Schedule& sc : {Schedule{false, 1, 0}, Schedule{true, 1, 0}, Schedule{false, 2, 0},
                             Schedule{true, 2, 1}, Schedule{true, 2, 2}, Schedule{true, 3, 2}}) {
    const std::string name = "background " + std::to_string(sc.background) + " every " +
                             std::to_string(sc.every) + " steps " + std::to_string(sc.steps);
    ForecastModelOptions o;
    o.meanTangent = true;
    o.tangentInBackground = sc.background;
    o.tangentRefreshEvery = sc.every;
    o.tangentBackgroundSteps = sc.steps;
    const int adoptAfter = sc.background ? std::max(sc.steps, 1) : 0;
    auto shared = std::make_shared<SharedFactorization>();
    MechanicalForecastModel w0(at8000, euler, {}, params, initial, o, 0, shared);
    MechanicalForecastModel w1(at8000, euler, {}, params, initial, o, 1, shared);
    ASSERT_TRUE(shared->tangent);
    std::vector<MechanicalState> means{initial};  // analysed means, step by step
    Eigen::VectorXd state = w0.packState(initial), a, b, p;
    for (int step = 1; step <= kSteps; ++step) {
      w0.forecast(state, E0, a, p);
      w1.forecast(state, E1, b, p);
      // Expected: eq. 2.16 with E1's forces and the tangent of the mean (E0) built at the last
      // multiple of N whose tangent was adopted by the end of the previous step.
      const int built = std::max(step - 1 - adoptAfter, 0) / sc.every * sc.every;
      MechanicalState s = means.back();
      ImplicitEuler direct(at9500, makeLinearSolver("cholmod"), euler);
      direct.stepWithTangent(at9500, s, *FrozenTangent::build(at8000, means[built], 0.01));
      const Eigen::Index n = s.x.size();
      EXPECT_LT((b.head(n) - s.x).norm(), 1e-12 * s.x.norm()) << name << " step " << step;
      EXPECT_LT((b.tail(n) - s.v).norm(), 1e-9 * s.v.norm()) << name << " step " << step;
      w0.endStep(a, E0);
      w1.endStep(a, E0);
      means.push_back(w0.reference());
      state = a;
    }
    // The tangents adopted: the first at construction, then every N steps from the first
    // adopted at step N + B.
    const ForecastStats cost = w0.takeStats();
    EXPECT_EQ(cost.forecasts, kSteps) << name;
    EXPECT_EQ(cost.factorizations, 1 + (kSteps - adoptAfter) / sc.every) << name;
    EXPECT_EQ(cost.linearIterations, 0) << name;
    EXPECT_EQ(w0.takeStats().forecasts, 0) << name;
  }
}

// A background build cannot be given longer than until the next one is due.
TEST(MechanicalForecastModel, BackgroundStepsBeyondTheRefreshIntervalAreRefused) {
  const MechanicalModel model = cylinderModel();
  ForecastModelOptions o;
  o.meanTangent = true;
  o.tangentInBackground = true;
  o.tangentRefreshEvery = 2;
  o.tangentBackgroundSteps = 3;
  EXPECT_THROW(MechanicalForecastModel(model, {0.01, 0, 1e-10}, {}, {}, model.restState(), o, 0,
                                       std::make_shared<SharedFactorization>()),
               std::invalid_argument);
}

// tangentSinglePrecision: the same steps through the factor rounded to float — not the same bits
// (so the float path is taken), within rounding of the double steps' increments.
TEST(MechanicalForecastModel, SinglePrecisionTangentStepsWithinRoundingOfTheDoubleOnes) {
  const MechanicalModel model = cylinderModel();
  const MechanicalState initial = model.restState();
  const std::vector<ModelParameterTarget> params{YoungModulusTarget{0, "stvk", 0.45}};
  const ImplicitEulerOptions euler{0.01, 0, 1e-10};
  MechanicalModel at8000 = model;
  applyParameter(params[0], 8000.0, at8000);
  const Eigen::VectorXd E0 = Eigen::VectorXd::Constant(1, 8000.0);
  const Eigen::VectorXd E1 = Eigen::VectorXd::Constant(1, 9500.0);
  for (bool background : {false, true}) {
    ForecastModelOptions o;
    o.meanTangent = true;
    o.tangentInBackground = background;
    ForecastModelOptions single = o;
    single.tangentSinglePrecision = true;
    auto sharedD = std::make_shared<SharedFactorization>();
    auto sharedS = std::make_shared<SharedFactorization>();
    MechanicalForecastModel d0(at8000, euler, {}, params, initial, o, 0, sharedD);
    MechanicalForecastModel d1(at8000, euler, {}, params, initial, o, 1, sharedD);
    MechanicalForecastModel s0(at8000, euler, {}, params, initial, single, 0, sharedS);
    MechanicalForecastModel s1(at8000, euler, {}, params, initial, single, 1, sharedS);
    Eigen::VectorXd state = d0.packState(initial), a, b, c, e, p;
    const Eigen::Index n = state.size() / 2;
    for (int step = 1; step <= 4; ++step) {
      d0.forecast(state, E0, a, p);
      d1.forecast(state, E1, b, p);
      s0.forecast(state, E0, c, p);
      s1.forecast(state, E1, e, p);
      const double increment = (b.head(n) - state.head(n)).norm();
      const double gap = (e.head(n) - b.head(n)).norm();
      EXPECT_GT(gap, 0.0) << background << " step " << step;
      EXPECT_LT(gap, 1e-5 * increment) << background << " step " << step;
      EXPECT_LT((c.head(n) - a.head(n)).norm(), 1e-5 * (a.head(n) - state.head(n)).norm())
          << background << " step " << step;
      // Both filters continue from the double mean, so that the gap does not compound here.
      for (auto* w : {&d0, &d1, &s0, &s1}) w->endStep(a, E0);
      state = a;
    }
  }
}

// One tet (legs 10 cm, base fixed) whose apex a load pushes 1.1 times its height through the base
// in one linear step of 10 ms: its two halves keep it above (tests/mechanics/test_step_recovery).
// Corotational: the linear law's response along the normal, but an inverted tet fails it.
MechanicalModel flattenedTet() {
  auto mesh = std::make_shared<TetMesh>();
  mesh->V.resize(4, 3);
  mesh->V << 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1;
  mesh->T.resize(1, 4);
  mesh->T << 0, 1, 2, 3;
  MechanicalModel model = makeMechanicalModel(
      std::move(mesh), {makeMaterial("corotational", 1000, 0.3)}, 1000, MassKind::Lumped);
  model.dirichlet = DirichletConditions({{{0, 1, 2}}}, *model.pattern);
  model.loads.push_back({{3}, Vec3(0, 0, -48.3013), {}});
  return model;
}

// A sigma point's step is halved where it fails, as any step, with its own tangent or the mean's;
// the halvings are counted in the worker's stats (timing.csv's step_retries). At min_dt the
// failure reaches the filter as an error.
TEST(MechanicalForecastModel, FailedForecastStepsAreHalvedAndCounted) {
  const MechanicalModel model = flattenedTet();
  const MechanicalState initial = model.restState();
  const Eigen::VectorXd none(0);
  for (bool meanTangent : {false, true}) {
    SCOPED_TRACE(meanTangent ? "mean tangent" : "own tangent");
    ForecastModelOptions o;
    o.solver = "cholmod";
    o.meanTangent = meanTangent;
    auto shared = std::make_shared<SharedFactorization>();
    MechanicalForecastModel w(model, {0.01, 0, 1e-10}, {}, {}, initial, o, 0, shared);
    Eigen::VectorXd state = w.packState(initial), next, predicted;
    w.forecast(state, none, next, predicted);
    EXPECT_EQ(w.takeStats().stepRetries, 1);
    EXPECT_GT(next(11), 0.0);  // the apex is still above the base
    EXPECT_EQ(model.elasticity.countInverted(next.head(12)), 0);

    ImplicitEulerOptions noHalving{0.01, 0, 1e-10};
    noHalving.minDt = 0.01;
    MechanicalForecastModel strict(model, noHalving, {}, {}, initial, o, 0, shared);
    EXPECT_THROW(strict.forecast(state, none, next, predicted), StepFailure);
  }
}

// An iterated static frame (RoukfOptions::reforecasts): recentre() makes the analysed mean's
// equilibrium at the frame's own time the reference (close enough to linearise about), forecasts
// then solve for that same time, and endStep() still ends that frame at its exact equilibrium;
// where the stiffness in use already solves the new mean at once, a re-forecast is said not to be
// worthwhile.
TEST(MechanicalForecastModel, RecentringAStaticFrameKeepsItsTimeAndSaysWhenItCannotHelp) {
  MechanicalModel model = cylinderModel();  // its load a sine of time: each frame's differs
  const std::vector<MappedPoint> observed = mapPoints(*model.mesh, model.mesh->V.topRows(5));
  ForecastModelOptions options;
  options.solver = "cholmod";
  options.statics = StaticOptions{};
  options.statics->relativeTolerance = 1e-10;
  options.meanTangent = true;
  options.layout.positions = options.layout.velocities = false;  // parameters only
  const double dt = 0.2;
  const YoungModulusTarget young{0, "stvk", 0.45};
  MechanicalForecastModel adapter(model, {dt, 0, 1e-10}, observed, {young}, model.restState(),
                                  options, 0, std::make_shared<SharedFactorization>());
  // The equilibrium at E = 6000 Pa and time t, solved apart.
  const auto equilibrium = [&](double t) {
    MechanicalModel direct = model;
    direct.elasticity.setMaterial(0, makeMaterial("stvk", 6000, 0.45));
    StaticSolver solver(direct, makeLinearSolver("cholmod"), *options.statics);
    Eigen::VectorXd x = direct.restPositions();
    solver.solve(direct, t, x);
    return x;
  };
  const Eigen::VectorXd atFrame = equilibrium(dt);
  const double motion = (atFrame - model.restPositions()).norm();
  ASSERT_GT(motion, 1e-4);

  const Eigen::VectorXd E = Eigen::VectorXd::Constant(1, 6000.0);
  // The rest shape's stiffness (E = 8000) does not solve it at once: worth re-forecasting. The
  // re-centred mean is a linearisation point, solved to 1 % of the forces (not to the scene's
  // 1e-10), a fraction of a percent of the motion here.
  EXPECT_TRUE(adapter.recentre(Eigen::VectorXd(), E));
  EXPECT_NEAR(adapter.reference().t, dt, 1e-15);
  const double recentredOff = (adapter.reference().x - atFrame).norm();
  EXPECT_LT(recentredOff, 1e-2 * motion);
  // A forecast now solves for the same time: one chord step from there lands on the equilibrium
  // to second order.
  Eigen::VectorXd newState, predicted;
  adapter.forecast(Eigen::VectorXd(), E, newState, predicted);
  for (int i = 0; i < 5; ++i)
    EXPECT_LT((predicted.segment<3>(3 * i) - interpolate(observed[i], *model.mesh, atFrame)).norm(),
              1e-2 * recentredOff)
        << recentredOff / motion;
  // Again at the same mean: the stiffness built there solves it at once.
  EXPECT_FALSE(adapter.recentre(Eigen::VectorXd(), E));
  EXPECT_NEAR(adapter.reference().t, dt, 1e-15);
  // The frame ends at its own time; the next one solves for the time after.
  adapter.endStep(Eigen::VectorXd(), E);
  EXPECT_NEAR(adapter.reference().t, dt, 1e-15);
  EXPECT_LT((adapter.reference().x - atFrame).norm(), 1e-7 * motion);
  adapter.forecast(Eigen::VectorXd(), E, newState, predicted);
  adapter.endStep(Eigen::VectorXd(), E);
  EXPECT_NEAR(adapter.reference().t, 2 * dt, 1e-15);
  EXPECT_LT((adapter.reference().x - equilibrium(2 * dt)).norm(), 1e-7 * motion);

  // A dynamic model cannot re-centre.
  ForecastModelOptions dynamicOptions;
  dynamicOptions.solver = "cholmod";
  MechanicalForecastModel dynamic(model, {0.01, 0, 1e-10}, observed, {young}, model.restState(),
                                  dynamicOptions, 0, nullptr);
  EXPECT_FALSE(dynamic.recentre(dynamic.packState(model.restState()), E));
  EXPECT_EQ(dynamic.reference().t, 0.0);
}

}  // namespace
}  // namespace bcassim
