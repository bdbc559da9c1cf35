// The library never half-solves: every material but the linear one reports an inverted element
// (the linear law takes it and solves in one linear system), statics converge at once under zero
// and tiny loads, failed load increments and time steps are halved until they succeed, and what
// cannot be mended is an error naming the time and the cause.
#include <gtest/gtest.h>

#include <regex>

#include "FemTestHelpers.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {
namespace {
using testing::boxModel;
using testing::nodesWhere;

constexpr double kEdge = 0.1;  // m: legs of the single tet, and its height H over the base
constexpr double kDensity = 1000.0;

// One tet: the right-angled base (0, 0, 0), (L, 0, 0), (0, L, 0) fixed, the apex (0, 0, L) free
// and pushed towards the base by f (N). The apex's shape gradient is n / H (n the base's unit
// normal), so its stiffness block is V / H^2 (mu I + (mu + lambda) n n^T): along n, with the
// lumped mass m = rho V / 4, the apex is a one-dof oscillator m u'' + k u = f, k = V (2 mu +
// lambda) / H^2 for the linear material, and det F = 1 - u / H. The corotational law is the same
// oscillator while det F > 0 (F = diag(1, 1, 1 - u / H) is its own stretch, R = I) and, unlike the
// linear law, fails an inverted tet: the step-halving tests use it.
MechanicalModel singleTet(const Material& material, double force) {
  auto mesh = std::make_shared<TetMesh>();
  mesh->V.resize(4, 3);
  mesh->V << 0, 0, 0, kEdge, 0, 0, 0, kEdge, 0, 0, 0, kEdge;
  mesh->T.resize(1, 4);
  mesh->T << 0, 1, 2, 3;
  MechanicalModel model =
      makeMechanicalModel(std::move(mesh), {material}, kDensity, MassKind::Lumped);
  model.dirichlet = DirichletConditions({{{0, 1, 2}}}, *model.pattern);
  model.loads.push_back({{3}, Vec3(0, 0, -force), {}});
  return model;
}

constexpr double kVolume = kEdge * kEdge * kEdge / 6.0;
constexpr double kApexMass = kDensity * kVolume / 4.0;
const LameParameters kLame = LameParameters::fromYoungPoisson(1000.0, 0.3);
const double kApexStiffness = kVolume * (2 * kLame.mu + kLame.lambda) / (kEdge * kEdge);

// The apex load whose one linear backward-Euler step of h from rest moves the apex by u:
// (m + h^2 k) u / h^2 = f.
double forceForStep(double u, double h) {
  return u * (kApexMass + h * h * kApexStiffness) / (h * h);
}

// Every tet of the box mirrored through z = 0: det F = -1 in each.
Eigen::VectorXd mirrored(const MechanicalModel& model) {
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 2; i < x.size(); i += 3) x(i) = -x(i);
  return x;
}

std::vector<Material> allMaterials() {
  std::vector<Material> out;
  for (const char* name : {"linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"})
    out.push_back(makeMaterial(name, 1000.0, 0.3));
  return out;
}

// Every law but the linear one: those that take no inverted state.
std::vector<Material> materialsFailingInversion() {
  std::vector<Material> out;
  for (const char* name : {"corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"})
    out.push_back(makeMaterial(name, 1000.0, 0.3));
  return out;
}

// --- det F <= 0 ------------------------------------------------------------------------------

TEST(InvertedElement, EveryMaterialButLinearReportsTheFirstInvertedTetAndItsDetF) {
  for (const Material& material : materialsFailingInversion()) {
    SCOPED_TRACE(materialName(material));
    const MechanicalModel model = boxModel(Vec3(0.02, 0.02, 0.02), 2, 2, 2, material);
    const Eigen::VectorXd x = mirrored(model);
    const Eigen::Index tets = model.mesh->numTets();
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    SparseMatrix K = model.pattern->emptyMatrix();
    auto expectAllInverted = [&](const std::function<void()>& evaluate) {
      try {
        evaluate();
        ADD_FAILURE() << "no InvertedElementError";
      } catch (const InvertedElementError& e) {
        EXPECT_EQ(e.element(), 0);
        EXPECT_NEAR(e.detF(), -1.0, 1e-12);
        EXPECT_EQ(e.count(), tets);
        EXPECT_EQ(std::string(e.what()), "element 0 inverted (det F = -1; " + std::to_string(tets) +
                                             " tets with det F <= 0)");
      }
    };
    expectAllInverted([&] { model.elasticity.addInternalForces(x, f); });
    expectAllInverted([&] { model.elasticity.addForcesAndStiffness(x, *model.pattern, 1, f, K); });
    expectAllInverted([&] { model.elasticity.requireNoInverted(x); });
    EXPECT_NO_THROW(model.elasticity.requireNoInverted(model.restPositions()));
  }
}

TEST(InvertedElement, OneCollapsedTetIsNamedWithItsDetF) {
  for (const Material& material : materialsFailingInversion()) {
    SCOPED_TRACE(materialName(material));
    const MechanicalModel model = singleTet(material, 0.0);
    Eigen::VectorXd x = model.restPositions();
    x(11) = -0.5 * kEdge;  // the apex half a height through the base: det F = -0.5
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    try {
      model.internalForces(0.0, x, f);
      ADD_FAILURE() << "no InvertedElementError";
    } catch (const InvertedElementError& e) {
      EXPECT_EQ(std::string(e.what()), "element 0 inverted (det F = -0.5)");
      EXPECT_NEAR(e.detF(), -0.5, 1e-12);
    }
    x(11) = 0.0;  // flat: det F = 0 is inverted too
    EXPECT_THROW(model.elasticity.requireNoInverted(x), InvertedElementError);
  }
}

TEST(InvertedElement, MeanDilatationPatchesReportItToo) {
  for (const char* name : {"stvk", "neohookean"}) {
    SCOPED_TRACE(name);
    auto mesh = std::make_shared<const TetMesh>(makeBoxMesh(Vec3(0.02, 0.02, 0.02), 2, 2, 2));
    const MechanicalModel model =
        makeMechanicalModel(mesh, {makeMaterial(name, 1000.0, 0.45)}, 1000.0, MassKind::Lumped, 4);
    const Eigen::VectorXd x = mirrored(model);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    try {
      model.elasticity.addInternalForces(x, f);
      ADD_FAILURE() << "no InvertedElementError";
    } catch (const InvertedElementError& e) {
      EXPECT_NEAR(e.detF(), -1.0, 1e-12);
      EXPECT_EQ(e.count(), mesh->numTets());
    }
  }
}

// Mirrored, every linear tet has det F = -1 and is evaluated all the same: f_int = K (x - X),
// the law being exactly linear.
TEST(InvertedElement, TheLinearLawTakesInvertedTets) {
  const MechanicalModel model =
      boxModel(Vec3(0.02, 0.02, 0.02), 2, 2, 2, makeMaterial("linear", 1000.0, 0.3));
  const Eigen::VectorXd rest = model.restPositions();
  const Eigen::VectorXd x = mirrored(model);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size()), f0 = f;
  SparseMatrix K = model.pattern->emptyMatrix();
  model.elasticity.addForcesAndStiffness(rest, *model.pattern, 1, f0, K);
  EXPECT_NO_THROW(model.elasticity.addInternalForces(x, f));
  EXPECT_EQ(model.elasticity.lastInvertedCount(), 0);
  EXPECT_NO_THROW(model.elasticity.requireNoInverted(x));
  EXPECT_EQ(model.elasticity.countInverted(x), 0);
  const Eigen::VectorXd expected = K * (x - rest);
  EXPECT_LT((f - expected).norm(), 1e-12 * expected.norm());
}

// Two regions, linear and Neo-Hookean: only the Neo-Hookean tets count as inverted.
TEST(InvertedElement, OnlyTheRegionsOfLawsThatFailInversionCountIt) {
  auto mesh = std::make_shared<TetMesh>(makeBoxMesh(Vec3(0.02, 0.02, 0.02), 2, 2, 2));
  mesh->region = Eigen::VectorXi::Zero(mesh->numTets());
  Eigen::Index neoHookeanTets = 0, firstNeoHookean = -1;
  for (Eigen::Index t = 0; t < mesh->numTets(); ++t)
    if (mesh->V.row(mesh->T(t, 0)).x() + mesh->V.row(mesh->T(t, 1)).x() +
            mesh->V.row(mesh->T(t, 2)).x() + mesh->V.row(mesh->T(t, 3)).x() >
        4 * 0.01) {  // centroid in x > 1 cm
      mesh->region(t) = 1;
      if (neoHookeanTets++ == 0) firstNeoHookean = t;
    }
  ASSERT_GT(neoHookeanTets, 0);
  ASSERT_LT(neoHookeanTets, mesh->numTets());
  const MechanicalModel model = makeMechanicalModel(
      std::move(mesh),
      {makeMaterial("linear", 1000.0, 0.3), makeMaterial("neohookean", 1000.0, 0.3)}, kDensity,
      MassKind::Lumped);
  const Eigen::VectorXd x = mirrored(model);
  EXPECT_EQ(model.elasticity.countInverted(x), neoHookeanTets);
  try {
    model.elasticity.requireNoInverted(x);
    ADD_FAILURE() << "no InvertedElementError";
  } catch (const InvertedElementError& e) {
    EXPECT_EQ(e.element(), firstNeoHookean);
    EXPECT_EQ(e.count(), neoHookeanTets);
  }
}

// --- the linear law pushed through inversion ---------------------------------------------------

// A 2 cm cube, base fixed, its top face pushed down by 2 N at E = 1 kPa: the linear response
// (about 10 cm, five times the height) inverts tets.
constexpr double kPushForce = 2.0;  // N, total on the top face

MechanicalModel pushedCube(const Material& material) {
  MechanicalModel model = boxModel(Vec3(0.02, 0.02, 0.02), 2, 2, 2, material);
  const TetMesh& mesh = *model.mesh;
  model.dirichlet = DirichletConditions(
      {{nodesWhere(mesh, [](const Vec3& p) { return p.z() < 1e-12; })}}, *model.pattern);
  const auto top = nodesWhere(mesh, [](const Vec3& p) { return p.z() > 0.02 - 1e-12; });
  model.loads.push_back({top, Vec3(0, 0, -kPushForce / static_cast<double>(top.size())), {}});
  return model;
}

// Displacement u (3N, m; 0 on the fixed dofs) solving (massOverH2 M + K) u = f_ext on the free
// dofs, K the stiffness at rest: the linear solve, by a dense factorisation.
Eigen::VectorXd linearResponse(const MechanicalModel& model, double massOverH2) {
  const Eigen::VectorXd rest = model.restPositions();
  const Eigen::Index n = rest.size();
  Eigen::VectorXd f0 = Eigen::VectorXd::Zero(n), fext;
  SparseMatrix K = model.pattern->emptyMatrix();
  model.elasticity.addForcesAndStiffness(rest, *model.pattern, 1, f0, K);
  model.externalForces(0.0, fext);
  Eigen::MatrixXd A = Eigen::MatrixXd(K);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(n, i), Me;
    model.mass.multiply(e, Me);
    A.col(i) += massOverH2 * Me;
  }
  std::vector<bool> fixed(n, false);
  for (int d : model.dirichlet.constrainedDofs()) fixed[d] = true;
  std::vector<Eigen::Index> free;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!fixed[i]) free.push_back(i);
  const Eigen::Index m = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd Aff(m, m);
  Eigen::VectorXd ff(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    ff(i) = fext(free[i]);
    for (Eigen::Index j = 0; j < m; ++j) Aff(i, j) = A(free[i], free[j]);
  }
  const Eigen::VectorXd uf = Aff.ldlt().solve(ff);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < m; ++i) u(free[i]) = uf(i);
  return u;
}

// The tets with det F <= 0 at x, from the deformed edges' triple product (no material).
std::vector<Eigen::Index> invertedTets(const TetMesh& mesh, const Eigen::VectorXd& x) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    const Vec3 x0 = x.segment<3>(3 * mesh.T(t, 0));
    const Vec3 e1 = x.segment<3>(3 * mesh.T(t, 1)) - x0, e2 = x.segment<3>(3 * mesh.T(t, 2)) - x0,
               e3 = x.segment<3>(3 * mesh.T(t, 3)) - x0;
    if (e1.dot(e2.cross(e3)) <= 0) out.push_back(t);
  }
  return out;
}

TEST(LinearLawThroughInversion, StaticSolveIsOneNewtonIterationAndTheLinearSolve) {
  const MechanicalModel model = pushedCube(makeMaterial("linear", 1000.0, 0.3));
  const Eigen::VectorXd rest = model.restPositions();
  const Eigen::VectorXd expected = linearResponse(model, 0.0);
  ASSERT_FALSE(invertedTets(*model.mesh, rest + expected).empty());

  Eigen::VectorXd x = rest;
  StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-10, 50, 1});
  const StaticReport report = solver.solve(model, 0.0, x);
  EXPECT_EQ(report.iterations, 1);  // quadratic energy: the first Newton step is the solution
  EXPECT_EQ(report.retries, 0);
  EXPECT_LT((x - rest - expected).norm(), 1e-10 * expected.norm());
}

// One backward-Euler step of h from rest: (M / h^2 + K) u = f_ext. With h = 1 s the cube is
// nearly static and its tets invert; the linearised step and Newton on it give that u.
TEST(LinearLawThroughInversion, ImplicitEulerStepIsTheLinearSolveWithoutHalving) {
  const MechanicalModel model = pushedCube(makeMaterial("linear", 1000.0, 0.3));
  const double h = 1.0;
  const Eigen::VectorXd expected = linearResponse(model, 1.0 / (h * h));
  ASSERT_FALSE(invertedTets(*model.mesh, model.restPositions() + expected).empty());
  for (int newtonIterations : {0, 3}) {
    SCOPED_TRACE(newtonIterations);
    ImplicitEulerOptions options{h, newtonIterations, 1e-10};
    options.minDt = h;  // no halving: the step must succeed as it is
    ImplicitEuler euler(model, makeLinearSolver("cholmod"), options);
    MechanicalState s = model.restState();
    euler.step(model, s);
    EXPECT_EQ(euler.lastTimings().retries, 0);
    EXPECT_LT((s.x - model.restPositions() - expected).norm(), 1e-10 * expected.norm());
  }
}

// Neo-Hookean has the linear law's stiffness at rest, so its linearised step from rest ends where
// the linear one does, inverted: that is an error naming the first inverted tet, never a result.
TEST(LinearLawThroughInversion, NeoHookeanThereStillFailsNamingTheElement) {
  const MechanicalModel linear = pushedCube(makeMaterial("linear", 1000.0, 0.3));
  const MechanicalModel neoHookean = pushedCube(makeMaterial("neohookean", 1000.0, 0.3));
  const double h = 1.0;
  const Eigen::VectorXd x = linear.restPositions() + linearResponse(linear, 1.0 / (h * h));
  const std::vector<Eigen::Index> inverted = invertedTets(*linear.mesh, x);
  ASSERT_FALSE(inverted.empty());

  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  try {
    neoHookean.internalForces(0.0, x, f);
    ADD_FAILURE() << "no InvertedElementError";
  } catch (const InvertedElementError& e) {
    EXPECT_EQ(e.element(), inverted.front());
    EXPECT_EQ(e.count(), static_cast<Eigen::Index>(inverted.size()));
  }

  ImplicitEulerOptions options{h, 0, 1e-10};
  options.minDt = h;
  ImplicitEuler euler(neoHookean, makeLinearSolver("cholmod"), options);
  MechanicalState s = neoHookean.restState();
  try {
    euler.step(neoHookean, s);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    const std::string prefix =
        "implicit Euler at t = 0 s: element " + std::to_string(inverted.front()) + " inverted";
    EXPECT_EQ(std::string(e.what()).substr(0, prefix.size()), prefix) << e.what();
  }
}

// --- statics at zero and tiny loads ----------------------------------------------------------

// A cantilever of every material under an end load (N); returns the static solution.
struct StaticRun {
  StaticReport report;
  Eigen::VectorXd u;  // displacement, m
};
StaticRun cantilever(const Material& material, double load) {
  MechanicalModel model = boxModel(Vec3(0.1, 0.02, 0.02), 6, 2, 2, material);
  const TetMesh& mesh = *model.mesh;
  model.dirichlet = DirichletConditions(
      {{nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
  const auto tip = nodesWhere(mesh, [](const Vec3& p) { return p.x() > 0.1 - 1e-12; });
  model.loads.push_back({tip, Vec3(0, 0, -load / static_cast<double>(tip.size())), {}});
  Eigen::VectorXd x = model.restPositions();
  StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-10, 50, 1});
  StaticRun run;
  run.report = solver.solve(model, 0.0, x);
  run.u = x - model.restPositions();
  return run;
}

TEST(StaticRoundOff, ZeroLoadIsSolvedAtOnce) {
  for (const Material& material : allMaterials()) {
    SCOPED_TRACE(materialName(material));
    const StaticRun run = cantilever(material, 0.0);
    EXPECT_LE(run.report.iterations, 2);
    EXPECT_EQ(run.report.retries, 0);
    EXPECT_LT(run.u.cwiseAbs().maxCoeff(), 1e-15);  // m
  }
}

// 1e-9 N is deep in the linear range: the displacement is 1e-3 of the one under 1 uN, found in at
// most two Newton iterations (not 50 on round-off).
TEST(StaticRoundOff, TinyLoadConvergesInTwoIterationsToTheLinearResponse) {
  for (const Material& material : allMaterials()) {
    SCOPED_TRACE(materialName(material));
    const StaticRun tiny = cantilever(material, 1e-9);
    const StaticRun small = cantilever(material, 1e-6);
    EXPECT_LE(tiny.report.iterations, 2);
    EXPECT_EQ(tiny.report.retries, 0);
    EXPECT_GT(tiny.u.norm(), 0.0);
    EXPECT_LT((tiny.u - 1e-3 * small.u).norm(), 1e-4 * tiny.u.norm());
  }
}

// --- statics: load increments halved --------------------------------------------------------

// A Neo-Hookean cube stretched to 1.6 times its length by a prescribed displacement: more than
// three Newton iterations in one increment, fewer in halves of it.
struct Stretch {
  MechanicalModel model;
  Eigen::VectorXd x;
};
Stretch stretchedCube() {
  MechanicalModel model = boxModel(Vec3(1, 1, 1), 2, 2, 2, makeMaterial("neohookean", 1e4, 0.3));
  const TetMesh& mesh = *model.mesh;
  auto x0 = nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; });
  auto x1 = nodesWhere(mesh, [](const Vec3& p) { return p.x() > 1 - 1e-12; });
  auto y0 = nodesWhere(mesh, [](const Vec3& p) { return p.y() < 1e-12; });
  auto z0 = nodesWhere(mesh, [](const Vec3& p) { return p.z() < 1e-12; });
  model.dirichlet = DirichletConditions({{x0, Vec3::Zero(), {}, {true, false, false}},
                                         {y0, Vec3::Zero(), {}, {false, true, false}},
                                         {z0, Vec3::Zero(), {}, {false, false, true}},
                                         {x1, Vec3(0.6, 0, 0), {}, {true, false, false}}},
                                        *model.pattern);
  Eigen::VectorXd x = model.restPositions();
  return {std::move(model), std::move(x)};
}

TEST(StaticIncrements, FailedIncrementIsHalvedAndReachesTheSameEquilibrium) {
  Stretch reference = stretchedCube();
  StaticSolver patient(reference.model, makeLinearSolver("cholmod"), {1e-12, 50, 8});
  const StaticReport r0 = patient.solve(reference.model, 0.0, reference.x);
  EXPECT_EQ(r0.retries, 0);

  Stretch hurried = stretchedCube();
  StaticSolver solver(hurried.model, makeLinearSolver("cholmod"), {1e-12, 3, 1});
  const StaticReport report = solver.solve(hurried.model, 0.0, hurried.x);
  EXPECT_GT(report.retries, 0);
  EXPECT_LT((hurried.x - reference.x).norm(), 1e-9 * reference.x.norm());
}

TEST(StaticIncrements, NoCutAllowedIsTheExactError) {
  Stretch hurried = stretchedCube();
  StaticOptions options{1e-12, 3, 1};
  options.minIncrementFraction = 1.0;
  StaticSolver solver(hurried.model, makeLinearSolver("cholmod"), options);
  try {
    solver.solve(hurried.model, 0.0, hurried.x);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_EQ(e.time(), 0.0);
    EXPECT_TRUE(std::regex_match(
        e.what(), std::regex("static solver at t = 0 s: Newton did not converge in 3 iterations "
                             "\\(residual [0-9.e+-]+ N, tolerance [0-9.e+-]+ N\\) \\(time.min_dt "
                             "allows no cut of the load increment\\)")))
        << e.what();
  }
}

// --- implicit Euler: time steps halved -------------------------------------------------------

// One linear backward-Euler step of h from rest moves the apex 1.1 H through the base. With
// h^2 k = 0.054 m the apex flies almost freely, and backward Euler's overshoot of free flight
// shrinks with the step: its two halves (closed form below) move it 0.85 H. One retry.
struct HalvedStep {
  double h = 0.01;
  double force = forceForStep(1.1 * kEdge, 0.01);
  // Apex displacement after two linear backward-Euler steps of h / 2 from rest, m.
  double twoHalves() const {
    const double g = h / 2, a = kApexMass + g * g * kApexStiffness;
    const double v1 = g * force / a, u1 = g * v1;
    const double v2 = v1 + g * (force - kApexStiffness * u1 - g * kApexStiffness * v1) / a;
    return u1 + g * v2;
  }
};

TEST(StepHalving, InvertingStepIsRedoneAsTwoHalves) {
  const HalvedStep c;
  const MechanicalModel model = singleTet(makeMaterial("corotational", 1000.0, 0.3), c.force);
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), {c.h, 0, 1e-10});
  MechanicalState s = model.restState();
  euler.step(model, s);
  EXPECT_EQ(euler.lastTimings().retries, 1);
  EXPECT_NEAR(s.t, c.h, 1e-15);
  EXPECT_EQ(model.elasticity.countInverted(s.x), 0);
  EXPECT_NEAR(kEdge - s.x(11), c.twoHalves(), 1e-12 * kEdge);
  EXPECT_GT(s.x(11) / kEdge, 0.1);  // det F of the final state
}

TEST(StepHalving, AtTheFloorTheStepFailsNamingTheElement) {
  const HalvedStep c;
  const MechanicalModel model = singleTet(makeMaterial("corotational", 1000.0, 0.3), c.force);
  ImplicitEulerOptions options{c.h, 0, 1e-10};
  options.minDt = c.h;  // no halving
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), options);
  MechanicalState s = model.restState();
  try {
    euler.step(model, s);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_EQ(e.time(), 0.0);
    EXPECT_EQ(std::string(e.what()),
              "implicit Euler at t = 0 s: element 0 inverted (det F = -0.1) at the time step "
              "0.01 s (time.min_dt = 0.01 s allows no halving)");
  }
}

// Four times the load: the apex must be slowed over the step, which halving cannot do before
// dt / 2 (min_dt): the error names the smallest step tried and when it started.
TEST(StepHalving, HalvingDownToMinDtThenTheExactError) {
  const HalvedStep c;
  const MechanicalModel model = singleTet(makeMaterial("corotational", 1000.0, 0.3), 4 * c.force);
  ImplicitEulerOptions options{c.h, 0, 1e-10};
  options.minDt = c.h / 2;
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), options);
  MechanicalState s = model.restState();
  try {
    euler.step(model, s);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_EQ(e.time(), 0.0);
    EXPECT_TRUE(std::regex_match(
        e.what(), std::regex("implicit Euler at t = 0 s: element 0 inverted \\(det F = "
                             "-[0-9.]+\\) with the time step halved to 0.005 s "
                             "\\(time.min_dt = 0.005 s\\)")))
        << e.what();
  }
}

TEST(StepHalving, InvertedStartStateIsAnErrorAtOnce) {
  const MechanicalModel model = singleTet(makeMaterial("stvk", 1000.0, 0.3), 0.0);
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), {0.01, 0, 1e-10});
  MechanicalState s = model.restState();
  s.x(11) = -0.5 * kEdge;
  s.t = 0.25;
  try {
    euler.step(model, s);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_EQ(std::string(e.what()),
              "implicit Euler at t = 0.25 s: element 0 inverted (det F = -0.5) in the state the "
              "step starts from");
  }
  EXPECT_EQ(euler.lastTimings().retries, 0);
}

// The shared tangent serves steps of dt only: a failing step is redone as step() would, with the
// halves' own tangents, and ends where step() ends.
TEST(StepHalving, StepWithTangentFallsBackToHalvedOwnSteps) {
  const HalvedStep c;
  const MechanicalModel model = singleTet(makeMaterial("corotational", 1000.0, 0.3), c.force);
  const auto tangent = FrozenTangent::build(model, model.restState(), c.h);
  ImplicitEuler shared(model, makeLinearSolver("cholmod"), {c.h, 0, 1e-10});
  MechanicalState s = model.restState();
  shared.stepWithTangent(model, s, *tangent);
  EXPECT_EQ(shared.lastTimings().retries, 1);
  EXPECT_NEAR(kEdge - s.x(11), c.twoHalves(), 1e-12 * kEdge);
}

// A Newton loop that cannot reach its tolerance in the iterations allowed fails the step: with
// one iteration and a tolerance of 1e-300 (round-off is the floor), Neo-Hookean's nonlinearity
// leaves the first step above it, and halving does not help either.
TEST(StepHalving, NewtonNotConvergedIsAFailureNotAResult) {
  MechanicalModel model =
      boxModel(Vec3(0.1, 0.02, 0.02), 4, 1, 1, makeMaterial("neohookean", 1000.0, 0.3));
  const TetMesh& mesh = *model.mesh;
  model.dirichlet = DirichletConditions(
      {{nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
  model.gravity = Vec3(0, 0, -9.81);
  ImplicitEulerOptions options{0.01, 1, 1e-300};
  options.minDt = 0.01;
  ImplicitEuler euler(model, makeLinearSolver("cholmod"), options);
  MechanicalState s = model.restState();
  try {
    euler.step(model, s);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    EXPECT_TRUE(std::regex_match(
        e.what(), std::regex("implicit Euler at t = 0 s: Newton did not converge in 1 iteration "
                             "\\(residual [0-9.e+-]+ N s, tolerance [0-9.e+-]+ N s\\) at the time "
                             "step 0.01 s \\(time.min_dt = 0.01 s allows no halving\\)")))
        << e.what();
  }
}

}  // namespace
}  // namespace bcassim
