// FEM verification: patch test, uniaxial stretch against closed forms, stiffness against finite
// differences, cantilever convergence order, dynamics relaxing to statics, energy decay.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "FemTestHelpers.h"
#include "bcassim/mechanics/ImplicitEuler.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/SurfaceTraction.h"

namespace bcassim {
namespace {
using testing::boxModel;
using testing::nodesWhere;

std::vector<Material> allMaterials(double E, double nu) {
  std::vector<Material> out;
  for (const char* name : {"linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"})
    out.push_back(makeMaterial(name, E, nu));
  return out;
}

// Patch test: prescribe x = F X + c on the boundary of a distorted mesh; the static solution must
// reproduce the homogeneous field at every interior node (constant stress is in equilibrium).
TEST(FemPatchTest, HomogeneousDeformationReproducedForEveryMaterial) {
  TetMesh mesh = makeBoxMesh(Vec3(1, 1, 1), 3, 3, 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  auto onBoundary = [](const Vec3& p) {
    return (p.array() < 1e-12).any() || (p.array() > 1 - 1e-12).any();
  };
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    if (!onBoundary(mesh.V.row(i).transpose()))
      for (int k = 0; k < 3; ++k) mesh.V(i, k) += jitter(rng);
  auto shared = std::make_shared<const TetMesh>(mesh);
  Mat3 F;
  F << 1.06, 0.03, -0.02, 0.01, 0.97, 0.04, -0.03, 0.02, 1.03;
  const Vec3 c(0.01, -0.02, 0.03);

  for (const Material& material : allMaterials(5000.0, 0.3)) {
    MechanicalModel model = makeMechanicalModel(shared, {material}, 1000.0, MassKind::Lumped);
    std::vector<DirichletRegion> regions;
    for (int n : nodesWhere(mesh, onBoundary)) {
      const Vec3 X = mesh.V.row(n).transpose();
      regions.push_back({{n}, F * X + c - X, {}, {true, true, true}});
    }
    model.dirichlet = DirichletConditions(regions, *model.pattern);
    Eigen::VectorXd x = model.restPositions();
    StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-12, 30, 1});
    const StaticReport report = solver.solve(model, 0.0, x);
    EXPECT_TRUE(report.converged) << materialName(material);
    double worst = 0;
    for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) {
      const Vec3 X = mesh.V.row(i).transpose();
      worst = std::max(worst, (x.segment<3>(3 * i) - (F * X + c)).norm());
    }
    EXPECT_LT(worst, 1e-9) << materialName(material);
  }
}

// Lateral stretch b of a traction-free uniaxial test and the axial P11, solved independently here.
struct Uniaxial {
  double b, P11;
};
Uniaxial stvkUniaxial(double a, double lambda, double mu) {
  const double b = std::sqrt(1.0 - lambda * (a * a - 1.0) / (2.0 * (lambda + mu)));
  const double trE = 0.5 * (a * a - 1.0) + (b * b - 1.0);
  return {b, a * (lambda * trE + mu * (a * a - 1.0))};
}
Uniaxial neoHookeanUniaxial(double a, double lambda, double mu) {
  double b = 1.0;  // Newton on P22(b) = mu (b - 1/b) + lambda ln(a b^2) / b = 0
  for (int it = 0; it < 50; ++it) {
    const double r = mu * (b - 1 / b) + lambda * std::log(a * b * b) / b;
    const double dr = mu * (1 + 1 / (b * b)) + lambda * (2 - std::log(a * b * b)) / (b * b);
    b -= r / dr;
  }
  return {b, mu * (a - 1 / a) + lambda * std::log(a * b * b) / a};
}

void checkUniaxial(const Material& material, double lambda, double mu, const Uniaxial& expected,
                   double a) {
  MechanicalModel model = boxModel(Vec3(1, 1, 1), 2, 2, 2, material);
  const TetMesh& mesh = *model.mesh;
  auto x0 = nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; });
  auto x1 = nodesWhere(mesh, [](const Vec3& p) { return p.x() > 1 - 1e-12; });
  auto y0 = nodesWhere(mesh, [](const Vec3& p) { return p.y() < 1e-12; });
  auto z0 = nodesWhere(mesh, [](const Vec3& p) { return p.z() < 1e-12; });
  model.dirichlet = DirichletConditions({{x0, Vec3::Zero(), {}, {true, false, false}},
                                         {y0, Vec3::Zero(), {}, {false, true, false}},
                                         {z0, Vec3::Zero(), {}, {false, false, true}},
                                         {x1, Vec3(a - 1, 0, 0), {}, {true, false, false}}},
                                        *model.pattern);
  Eigen::VectorXd x = model.restPositions();
  StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-13, 50, 4});
  ASSERT_TRUE(solver.solve(model, 0.0, x).converged);
  Eigen::VectorXd f;
  model.internalForces(0.0, x, f);
  double reaction = 0;
  for (int n : x1) reaction += f(3 * n);  // the force the stretching grip exerts, N on 1 m^2
  EXPECT_NEAR(reaction / expected.P11, 1.0, 1e-6);
  const int corner = x1.back();  // (1,1,1): lateral positions give the lateral stretch
  EXPECT_NEAR(x(3 * corner + 1) / expected.b, 1.0, 1e-6);
  EXPECT_NEAR(x(3 * corner + 2) / expected.b, 1.0, 1e-6);
  (void)lambda;
  (void)mu;
}

TEST(FemUniaxialStretch, StvkMatchesClosedForm) {
  const auto L = LameParameters::fromYoungPoisson(1e4, 0.3);
  for (double a : {1.2, 0.85})
    checkUniaxial(StvkMaterial{L.lambda, L.mu}, L.lambda, L.mu, stvkUniaxial(a, L.lambda, L.mu), a);
}

TEST(FemUniaxialStretch, NeoHookeanMatchesClosedForm) {
  const auto L = LameParameters::fromYoungPoisson(1e4, 0.3);
  for (double a : {1.3, 0.8})
    checkUniaxial(NeoHookeanMaterial{L.lambda, L.mu}, L.lambda, L.mu,
                  neoHookeanUniaxial(a, L.lambda, L.mu), a);
}

// Uniaxial stretch driven by a force instead of a grip: a dead traction P11 on the face x = 1,
// made nodal forces by the surface-traction shares, must give the homogeneous stretch a at every
// node of that face. An even split of the same force over the face's nodes must not (corner
// nodes would get as much as the middle one): that is why loads have distribution: surface.
TEST(FemUniaxialStretch, SurfaceTractionGivesTheHomogeneousStretch) {
  const auto L = LameParameters::fromYoungPoisson(1e4, 0.3);
  const double a = 1.1;
  const Uniaxial expected = stvkUniaxial(a, L.lambda, L.mu);
  double spread[2] = {0, 0};
  for (bool consistent : {true, false}) {
    MechanicalModel model = boxModel(Vec3(1, 1, 1), 2, 2, 2, StvkMaterial{L.lambda, L.mu});
    const TetMesh& mesh = *model.mesh;
    auto x0 = nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; });
    auto y0 = nodesWhere(mesh, [](const Vec3& p) { return p.y() < 1e-12; });
    auto z0 = nodesWhere(mesh, [](const Vec3& p) { return p.z() < 1e-12; });
    model.dirichlet = DirichletConditions({{x0, Vec3::Zero(), {}, {true, false, false}},
                                           {y0, Vec3::Zero(), {}, {false, true, false}},
                                           {z0, Vec3::Zero(), {}, {false, false, true}}},
                                          *model.pattern);
    const auto traction =
        surfaceTractionShares(mesh, BoxRegion{Vec3(1 - 1e-9, -1, -1), Vec3(2, 2, 2)});
    NodalLoad load;
    load.nodes = traction.nodes;
    load.forcePerNode = Vec3(expected.P11 * traction.area, 0, 0);  // N: P11 on 1 m^2
    if (consistent)
      load.weights = traction.shares;
    else
      load.forcePerNode /= static_cast<double>(load.nodes.size());
    model.loads.push_back(load);
    Eigen::VectorXd x = model.restPositions();
    StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-13, 50, 4});
    ASSERT_TRUE(solver.solve(model, 0.0, x).converged);
    double lo = 1e9, hi = -1e9;
    for (int n : traction.nodes) {
      lo = std::min(lo, x(3 * n));
      hi = std::max(hi, x(3 * n));
    }
    spread[consistent] = hi - lo;
    if (consistent) {
      EXPECT_NEAR(lo, a, 1e-6);
      EXPECT_NEAR(hi, a, 1e-6);
      const int corner = traction.nodes.back();  // (1,1,1)
      EXPECT_NEAR(x(3 * corner + 1), expected.b, 1e-6);
    }
  }
  EXPECT_GT(spread[false], 1e-3);  // m: the even split bends the loaded face
}

// The assembled stiffness (elasticity + springs + control points) equals finite differences of
// the assembled internal forces, at random states with springs both stretched and slack.
TEST(FemStiffness, EqualsFiniteDifferencesOfForces) {
  for (const Material& material : allMaterials(8000.0, 0.45)) {
    MechanicalModel model = boxModel(Vec3(0.1, 0.04, 0.03), 3, 2, 2, material);
    const TetMesh& mesh = *model.mesh;
    std::vector<CubicSpring> springs;
    for (int t = 0; t < 6; ++t) {
      const Vec4 w(0.1 + 0.1 * t / 6.0, 0.2, 0.3, 0.4 - 0.1 * t / 6.0);
      Vec3 p = Vec3::Zero();
      for (int a = 0; a < 4; ++a) p += w(a) * mesh.V.row(mesh.T(t, a)).transpose();
      // Even springs start slack (anchor closer than rest length), odd ones stretched.
      springs.push_back({t, w, p + Vec3(0, 0.03, 0), t % 2 == 0 ? 0.05 : 0.02, t % 2});
    }
    model.springs = CubicSpringSet(springs, {{4e6, 7e4, 20}, {1e6, 3e4, 50}});
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 1e-3);
    Eigen::VectorXd x = model.restPositions();
    for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += noise(rng);
    Eigen::VectorXd f, fp, fm;
    SparseMatrix K;
    model.internalForcesAndStiffness(0.0, x, f, K);
    const Eigen::MatrixXd Kd = Eigen::MatrixXd(K);
    Eigen::MatrixXd Kfd(x.size(), x.size());
    const double h = 1e-7;
    for (Eigen::Index j = 0; j < x.size(); ++j) {
      Eigen::VectorXd xp = x, xm = x;
      xp(j) += h;
      xm(j) -= h;
      model.internalForces(0.0, xp, fp);
      model.internalForces(0.0, xm, fm);
      Kfd.col(j) = (fp - fm) / (2 * h);
    }
    EXPECT_LT((Kd - Kfd).norm() / Kd.norm(), 1e-6) << materialName(material);
  }
}

TEST(CubicSprings, ZeroForceAndZeroTangentInCompression) {
  const CubicSpringCoefficients k{4, 7, 20};
  for (double dl : {-0.1, -1e-6, 0.0}) {
    EXPECT_EQ(CubicSpringSet::magnitude(k, dl), 0.0);
    EXPECT_EQ(CubicSpringSet::magnitudeDerivative(k, dl), 0.0);
    EXPECT_EQ(CubicSpringSet::potential(k, dl), 0.0);
  }
  // Eq. 2.26 in tension, and g = d(potential)/d(dl), g' by central differences.
  const double dl = 0.02, h = 1e-6;
  EXPECT_DOUBLE_EQ(CubicSpringSet::magnitude(k, dl), 4 * dl * dl * dl + 7 * dl * dl + 20 * dl);
  EXPECT_NEAR(
      (CubicSpringSet::potential(k, dl + h) - CubicSpringSet::potential(k, dl - h)) / (2 * h),
      CubicSpringSet::magnitude(k, dl), 1e-9);
  EXPECT_NEAR(
      (CubicSpringSet::magnitude(k, dl + h) - CubicSpringSet::magnitude(k, dl - h)) / (2 * h),
      CubicSpringSet::magnitudeDerivative(k, dl), 1e-7);
}

TEST(CubicSprings, CutGroupExertsNoForceAfterCutTime) {
  MechanicalModel model = boxModel(Vec3(0.1, 0.1, 0.1), 1, 1, 1, makeMaterial("stvk", 1e4, 0.3));
  const Vec4 w(0.25, 0.25, 0.25, 0.25);
  model.springs = CubicSpringSet({{0, w, Vec3(0, 0, -1), 0.5, 0}}, {{1, 1, 1}});
  model.springs.cutGroupAt(0, 2.0);
  Eigen::VectorXd f;
  const Eigen::VectorXd x = model.restPositions();
  model.springs.addInternalForces(*model.mesh, x, 1.0, f = Eigen::VectorXd::Zero(x.size()));
  EXPECT_GT(f.norm(), 0.1);
  f.setZero();
  model.springs.addInternalForces(*model.mesh, x, 2.0, f);
  EXPECT_EQ(f.norm(), 0.0);
}

// Tip deflection of a clamped linear-elastic beam under an end load converges with mesh refinement
// at second order (P1 tets: the deflection is a smooth functional of a solution that converges at
// O(h) in energy) towards Euler-Bernoulli theory (with the small Timoshenko shear term).
TEST(FemCantilever, TipDeflectionConvergesAtSecondOrder) {
  const double L = 0.5, h = 0.1, E = 1e6, P = 1.0;
  std::vector<double> deflection;
  for (int n : {3, 6, 12}) {
    MechanicalModel model = boxModel(Vec3(L, h, h), 5 * n, n, n, makeMaterial("linear", E, 0.0));
    const TetMesh& mesh = *model.mesh;
    model.dirichlet = DirichletConditions(
        {{nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
    auto tip = nodesWhere(mesh, [&](const Vec3& p) { return p.x() > L - 1e-12; });
    model.loads.push_back({tip, Vec3(0, 0, -P / tip.size()), {}});
    Eigen::VectorXd x = model.restPositions();
    StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-9, 5, 1});
    ASSERT_TRUE(solver.solve(model, 0.0, x).converged);
    double mean = 0;
    for (int t : tip) mean += x(3 * t + 2) - mesh.V(t, 2);
    deflection.push_back(-mean / tip.size());
  }
  // Beam theory with Timoshenko's shear correction (kappa = 5/6) is the reference.
  const double I = h * h * h * h / 12.0, G = E / 2.0, A = h * h;
  const double theory = P * L * L * L / (3 * E * I) + P * L / (5.0 / 6.0 * G * A);
  std::vector<double> error;
  for (double d : deflection) error.push_back(std::abs(d - theory) / theory);
  const double coarseOrder = std::log2(error[0] / error[1]);
  const double fineOrder = std::log2(error[1] / error[2]);
  // Linear tets lock in bending, so the coarse pair is pre-asymptotic; the order rises towards 2.
  EXPECT_GT(fineOrder, coarseOrder);
  EXPECT_NEAR(fineOrder, 2.0, 0.3) << "errors " << error[0] << " " << error[1] << " " << error[2];
  EXPECT_LT(error[2], 0.03);
}

// With damping and a constant load, implicit Euler relaxes to the static Newton solution.
TEST(FemDynamics, DampedImplicitEulerConvergesToStaticEquilibrium) {
  MechanicalModel model =
      boxModel(Vec3(0.15, 0.03, 0.03), 10, 2, 2, makeMaterial("stvk", 5e4, 0.45), 1000.0);
  const TetMesh& mesh = *model.mesh;
  model.dirichlet = DirichletConditions(
      {{nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
  model.gravity = Vec3(0, 0, -9.81);
  model.rayleighMass = 5.0;
  model.rayleighStiffness = 0.01;

  Eigen::VectorXd xs = model.restPositions();
  StaticSolver statics(model, makeLinearSolver("cholmod"), {1e-12, 50, 2});
  ASSERT_TRUE(statics.solve(model, 0.0, xs).converged);

  ImplicitEuler euler(model, makeLinearSolver("cholmod"), {0.01, 0, 1e-10});
  MechanicalState s = model.restState();
  for (int i = 0; i < 3000 && (i < 10 || s.v.norm() > 1e-12); ++i) euler.step(model, s);
  const Eigen::VectorXd us = xs - model.restPositions(), ud = s.x - model.restPositions();
  EXPECT_LT((ud - us).norm() / us.norm(), 1e-6);
}

// Without loads or damping, backward Euler never increases kinetic + stored energy.
TEST(FemDynamics, EnergyNeverIncreasesWithoutLoads) {
  for (int newton : {0, 4}) {
    MechanicalModel model =
        boxModel(Vec3(0.15, 0.03, 0.03), 10, 2, 2, makeMaterial("stvk", 5e4, 0.45), 1000.0);
    const TetMesh& mesh = *model.mesh;
    model.dirichlet = DirichletConditions(
        {{nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
    ImplicitEuler euler(model, makeLinearSolver("cholmod"), {0.005, newton, 1e-12});
    MechanicalState s = model.restState();
    for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)  // initial velocity: bending mode
      s.v(3 * i + 2) = 0.5 * std::pow(mesh.V(i, 0) / 0.15, 2);
    model.dirichlet.zeroConstrained(s.v);
    double previous = model.mass.kineticEnergy(s.v) + model.storedEnergy(0, s.x);
    const double initial = previous;
    for (int i = 0; i < 300; ++i) {
      euler.step(model, s);
      const double energy = model.mass.kineticEnergy(s.v) + model.storedEnergy(s.t, s.x);
      ASSERT_LE(energy, previous * (1 + 1e-12)) << "step " << i << " newton " << newton;
      previous = energy;
    }
    EXPECT_LT(previous, initial);
  }
}

// The extrapolated initial guess changes where PCG starts, not where it ends: the same
// trajectory to the solver's tolerance, in fewer iterations under a smooth periodic load.
TEST(FemDynamics, ExtrapolatedGuessKeepsTheTrajectoryAndSavesIterations) {
  Eigen::VectorXd finalX[2];
  int iterations[2] = {0, 0};
  for (bool extrapolate : {false, true}) {
    MechanicalModel model =
        boxModel(Vec3(0.15, 0.03, 0.03), 12, 3, 3, makeMaterial("stvk", 8e3, 0.49), 1000.0);
    const TetMesh& mesh = *model.mesh;
    model.dirichlet = DirichletConditions(
        {{nodesWhere(mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
    NodalLoad load;
    load.nodes = nodesWhere(mesh, [](const Vec3& p) { return p.x() > 0.15 - 1e-12; });
    load.forcePerNode = Vec3(0, 0, -0.05 / static_cast<double>(load.nodes.size()));
    load.profile.kind = TimeProfile::Kind::Sine;
    load.profile.period = 1.0;
    model.loads.push_back(load);
    model.rayleighMass = 0.1;
    model.rayleighStiffness = 0.01;
    RefreshPolicy policy;
    policy.maxIterations = 200;  // never refactorise: count the iterations from one factor
    ImplicitEulerOptions options{0.01, 0, 1e-10};
    options.extrapolateGuess = extrapolate;
    ImplicitEuler euler(model, makeLinearSolver("factorized-pcg", policy), options);
    MechanicalState s = model.restState();
    for (int i = 0; i < 40; ++i) {
      euler.step(model, s);
      iterations[extrapolate] += euler.lastTimings().lastSolve.iterations;
    }
    finalX[extrapolate] = s.x - model.restPositions();
  }
  EXPECT_LT((finalX[1] - finalX[0]).norm() / finalX[0].norm(), 1e-7);
  EXPECT_LT(iterations[1], iterations[0]);
}

}  // namespace
}  // namespace bcassim
