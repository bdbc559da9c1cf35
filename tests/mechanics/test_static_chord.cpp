// Chord iterations with a frozen static tangent (StaticSolver::chordSolve, FrozenTangent::
// buildStatic): they reach Newton's equilibrium from another one, prescribed motion included; for
// the linear law one step from the tangent's own state is the exact solution; springs with other
// coefficients than the tangent's are exact through the low-rank correction; a chord that cannot
// converge says so instead of returning a half-solved state, and one cut short how many steps it
// still needs and goes on as one chord; a step that inverts an element throws.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>

#include "FemTestHelpers.h"
#include "bcassim/mechanics/ChunkedForces.h"
#include "bcassim/mechanics/InvertedElementError.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {
namespace {

// A 300-node cylinder of `law`: the base fixed, the tip pushed sideways by a prescribed motion
// growing with t, a sideways load at mid-length growing with t (ramps reaching 2 cm and 0.2 N at
// t = 10 s).
MechanicalModel chordCylinder(const std::string& law) {
  auto mesh = std::make_shared<const TetMesh>(makeCylinderMesh(0.015, 0.18, 300));
  MechanicalModel model =
      makeMechanicalModel(mesh, {makeMaterial(law, 8000, 0.45)}, 1000, MassKind::Lumped);
  const auto [base, tip, middle] = testing::cylinderNodes(*mesh, 0.015, 0.18);
  model.dirichlet = DirichletConditions(
      {{base}, {tip, Vec3(0.02, 0, 0), {TimeProfile::Kind::Ramp, 10.0}}}, *model.pattern);
  model.loads.push_back({middle, Vec3(0, 0.2 / middle.size(), 0), {TimeProfile::Kind::Ramp, 10.0}});
  return model;
}

// Newton's equilibrium at time t from the rest state.
Eigen::VectorXd newtonAt(const MechanicalModel& model, double t) {
  StaticSolver newton(model, makeLinearSolver("cholmod"), {1e-12, 50, 4});
  Eigen::VectorXd x = model.restPositions();
  newton.solve(model, t, x);
  return x;
}

// In double precision, and with the factor rounded to float (the residual stays in double, so
// the iterations still converge to the equilibrium, only more of them may be needed).
TEST(StaticChord, ReachesNewtonsEquilibriumFromAnotherOne) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd before = newtonAt(model, 1.0), exact = newtonAt(model, 1.2);
  const MechanicalState at{before, Eigen::VectorXd::Zero(before.size()), 1.0};
  const auto tangent = FrozenTangent::buildStatic(model, at);
  ASSERT_TRUE(tangent->isStatic());
  for (bool single : {false, true}) {
    StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
    Eigen::VectorXd x = before;
    const StaticReport report = chord.chordSolve(model, 1.2, x, *tangent, 30, single);
    ASSERT_TRUE(report.converged) << single;
    EXPECT_GE(report.iterations, 2);  // a nonlinear law: the first step alone is not the answer
    const double moved = (exact - before).norm();
    ASSERT_GT(moved, 1e-4);
    EXPECT_LT((x - exact).norm(), 1e-8 * moved) << single;
    const Eigen::VectorXd target = model.dirichlet.targetPositions(model.restPositions(), 1.2);
    for (Eigen::Index k = 0; k < target.size(); ++k)
      EXPECT_EQ(x(model.dirichlet.constrainedDofs()[k]), target(k));
  }
}

// A Newton solver that starts from a tangent's analysis (makeLinearSolver's `analysis`) and has
// factorised once at rest (StaticSolver::warmUp) reaches the equilibrium of one that analyses and
// factorises on its own, to the bit: what they save is the first solve's time.
TEST(StaticChord, ANewtonSolverOnATangentsAnalysisAndWarmedUpSolvesTheSameBits) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd own = newtonAt(model, 1.2);
  const auto tangent = FrozenTangent::buildStatic(model, model.restState());
  for (const char* solver : {"cholmod", "factorized-pcg"}) {
    StaticSolver newton(model, makeLinearSolver(solver, {}, &tangent->factor()), {1e-12, 50, 4});
    newton.warmUp(model, 0.0, model.restPositions());
    Eigen::VectorXd x = model.restPositions();
    newton.solve(model, 1.2, x);
    if (std::string(solver) == "cholmod")
      EXPECT_EQ(x, own);
    else  // PCG about the factor: the same equilibrium to its tolerance
      EXPECT_LT((x - own).norm(), 1e-8 * (own - model.restPositions()).norm());
  }
}

TEST(StaticChord, OneStepOfTheLinearLawIsTheExactSolution) {
  const MechanicalModel model = chordCylinder("linear");
  const auto tangent = FrozenTangent::buildStatic(model, model.restState());
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd x = model.restPositions();
  const StaticReport report = chord.chordSolve(model, 2.0, x, *tangent, 1);
  EXPECT_EQ(report.iterations, 1);
  const Eigen::VectorXd exact = newtonAt(model, 2.0);
  EXPECT_LT((x - exact).norm(), 1e-10 * (exact - model.restPositions()).norm());
}

// The cylinder with two groups of cubic springs on one side, near the tip (at least 4 springs),
// all taut (a spring's stiffness jumps where it goes slack: a tangent there would change with
// nanometres of motion).
MechanicalModel springCylinder() {
  MechanicalModel model = chordCylinder("neohookean");
  std::vector<CubicSpring> springs;
  for (int tet = 0; tet < model.mesh->numTets(); ++tet) {
    Vec3 centre = Vec3::Zero();
    for (int a = 0; a < 4; ++a) centre += 0.25 * model.mesh->V.row(model.mesh->T(tet, a));
    if (std::abs(centre.z() - 0.12) > 0.01 || centre.y() < 0.008) continue;
    springs.push_back({tet, Vec4::Constant(0.25), centre + Vec3(0.004, 0.01, 0.005), 0.005,
                       static_cast<int>(springs.size() % 2)});
  }
  model.springs = CubicSpringSet(springs, {{200, 0, 5e4}, {100, 0, 2e4}});
  return model;
}

// What the estimated parameters change: a tangent built with 10x softer springs still gives the
// step of the model's own tangent, since their stiffness is replaced exactly (Woodbury).
TEST(StaticChord, SpringsOfTheStepReplaceTheTangentsExactly) {
  const MechanicalModel model = springCylinder();
  ASSERT_GE(model.springs.springs().size(), 4u);
  const Eigen::VectorXd before = newtonAt(model, 1.0);
  const MechanicalState at{before, Eigen::VectorXd::Zero(before.size()), 1.0};
  MechanicalModel softer = model;
  softer.springs.setCoefficients(0, {20, 0, 5e3});
  softer.springs.setCoefficients(1, {10, 0, 2e3});
  const auto frozen = FrozenTangent::buildStatic(softer, at);
  const auto own = FrozenTangent::buildStatic(model, at);
  ASSERT_TRUE(frozen->correctsSprings());
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd a = before, b = before;
  chord.chordSolve(model, 1.3, a, *frozen, 1);
  chord.chordSolve(model, 1.3, b, *own, 1);
  ASSERT_GT((b - before).norm(), 1e-4);
  EXPECT_LT((a - b).norm(), 1e-9 * (b - before).norm());
}

// Newton's last factorisation as the tangent at its equilibrium (StaticSolver::newtonTangent): a
// chord step with it is the step of a tangent built there, to within Newton's last step (it was
// factorised one step before), the springs' correction included, and its chord reaches the next
// equilibrium. None where the solve made no factorisation or the solver keeps no exact factor.
TEST(StaticChord, NewtonsLastFactorServesAsTheTangentAtItsEquilibrium) {
  const MechanicalModel model = springCylinder();
  StaticSolver newton(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd x = newtonAt(model, 1.0);
  const auto before = FrozenTangent::buildStatic(model, {x, Eigen::VectorXd::Zero(x.size()), 1.0});
  newton.continueFrom(model, 1.0);
  EXPECT_EQ(newton.newtonTangent(model, {x, Eigen::VectorXd::Zero(x.size()), 1.0}), nullptr);
  ASSERT_GE(newton.solve(model, 1.2, x).iterations, 2);
  const MechanicalState at{x, Eigen::VectorXd::Zero(x.size()), 1.2};
  const auto reused = newton.newtonTangent(model, at);
  ASSERT_NE(reused, nullptr);
  ASSERT_TRUE(reused->correctsSprings());
  EXPECT_EQ(reused->buildSeconds(), reused->springSeconds());  // no assembly, no factorisation
  const auto built = FrozenTangent::buildStatic(model, at);
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd a = x, b = x, c = x;
  chord.chordSolve(model, 1.3, a, *reused, 1);
  chord.chordSolve(model, 1.3, b, *built, 1);
  chord.chordSolve(model, 1.3, c, *before, 1);  // the last equilibrium's tangent, for scale
  const double step = (b - x).norm();
  ASSERT_GT(step, 1e-3);
  EXPECT_LT((a - b).norm(), 1e-3 * step);
  EXPECT_LT((a - b).norm(), 1e-2 * (c - b).norm());
  EXPECT_GT((a - b).norm(), 0.0);  // it is the factor of the step before, not a new one
  Eigen::VectorXd y = x;
  ASSERT_TRUE(chord.chordSolve(model, 1.3, y, *reused, 30).converged);
  const Eigen::VectorXd exact = newtonAt(model, 1.3);
  EXPECT_LT((y - exact).norm(), 1e-8 * (exact - x).norm());

  // A solve already at its equilibrium factorises nothing: the tangent would be another point's.
  newton.solve(model, 1.2, x);
  EXPECT_EQ(newton.newtonTangent(model, at), nullptr);
  StaticSolver pcg(model, makeLinearSolver("factorized-pcg"), {1e-12, 50, 1});
  Eigen::VectorXd z = model.restPositions();
  pcg.solve(model, 1.2, z);
  EXPECT_EQ(pcg.newtonTangent(model, at), nullptr);
}

TEST(StaticChord, AChordThatCannotConvergeSaysSo) {
  // The rest tangent of a Neo-Hookean cylinder, asked for an equilibrium far out: the chord
  // crawls, and the solve stops unconverged rather than pass for an equilibrium.
  const MechanicalModel model = chordCylinder("neohookean");
  const auto tangent = FrozenTangent::buildStatic(model, model.restState());
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd x = model.restPositions();
  StaticReport report;
  try {
    report = chord.chordSolve(model, 12.0, x, *tangent, 4);
  } catch (const InvertedElementError&) {
    return;  // also a refusal
  }
  EXPECT_FALSE(report.converged);
  EXPECT_GT(report.residualNorm, 0.0);
}

// A chord cut short says how many more steps it needs at the contraction it had: that many from
// where it stopped reach the equilibrium. A converged, a one-step or a diverging chord cannot
// tell (INT_MAX).
TEST(StaticChord, ItsStepsToGoAreEnoughToFinishACutShortChord) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd before = newtonAt(model, 1.0);
  const auto tangent =
      FrozenTangent::buildStatic(model, {before, Eigen::VectorXd::Zero(before.size()), 1.0});
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd x = before;
  const StaticReport cut = chord.chordSolve(model, 1.4, x, *tangent, 3);
  ASSERT_FALSE(cut.converged);
  ASSERT_LT(cut.residualNorm, cut.initialResidualNorm);
  const int toGo = chordStepsToGo(cut);
  ASSERT_GT(toGo, 0);
  ASSERT_LT(toGo, 30);
  const StaticReport rest = chord.chordSolve(model, 1.4, x, *tangent, toGo);
  EXPECT_TRUE(rest.converged) << toGo << " steps to go, " << rest.residualNorm << " N left";
  EXPECT_EQ(chordStepsToGo(rest), std::numeric_limits<int>::max());  // converged

  StaticReport made;  // r0 = 1 N, 1e-4 N after 4 steps: 1e-1 per step; 2e-6 N asked
  made.iterations = 4;
  made.initialResidualNorm = 1;
  made.residualNorm = 1e-4;
  made.tolerance = 2e-6;
  EXPECT_EQ(chordStepsToGo(made), 2);
  made.iterations = 1;
  EXPECT_EQ(chordStepsToGo(made), std::numeric_limits<int>::max());
  made.iterations = 5;
  made.residualNorm = 2;  // it grew
  EXPECT_EQ(chordStepsToGo(made), std::numeric_limits<int>::max());
}

// Where a chord stops short, Newton finishes from its last iterate (as a static filter frame's
// mean does, MechanicalForecastModel::solveStaticFrom): the same equilibrium as Newton from the
// chord's start, in fewer iterations, each a factorisation.
TEST(StaticChord, NewtonFinishesAChordCutShortInFewerIterationsThanFromItsStart) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd before = newtonAt(model, 1.0);
  const auto tangent =
      FrozenTangent::buildStatic(model, {before, Eigen::VectorXd::Zero(before.size()), 1.0});
  Eigen::VectorXd loadBefore;
  model.externalForces(1.0, loadBefore);
  const StaticOptions options{1e-10, 50, 1};
  StaticSolver chord(model, makeLinearSolver("cholmod"), options);
  Eigen::VectorXd fromChord = before;
  const StaticReport cut = chord.chordSolve(model, 5.0, fromChord, *tangent, 10);
  ASSERT_FALSE(cut.converged);
  ASSERT_LT(cut.residualNorm, 0.5 * cut.initialResidualNorm);

  const auto newton = [&](Eigen::VectorXd& x) {
    StaticSolver solver(model, makeLinearSolver("cholmod"), options);
    solver.continueFromLoad(loadBefore);
    return solver.solve(model, 5.0, x).iterations;
  };
  Eigen::VectorXd fromBefore = before;
  const int itersFromBefore = newton(fromBefore);
  const int itersFromChord = newton(fromChord);
  std::cout << "[ chord then Newton ] Newton iterations from the last equilibrium "
            << itersFromBefore << ", from the chord's end " << itersFromChord << "\n";
  EXPECT_LT(itersFromChord, itersFromBefore);
  EXPECT_LT((fromChord - fromBefore).norm(), 1e-7 * (fromBefore - before).norm());
}

// A chord stopped at its cap reports the residual of the iterate it leaves (its last step is
// evaluated like the others), and continueChord goes on from there as if it had not stopped: the
// same iterate as one chord of all the steps, to the bit. Starting afresh (chordSolve again)
// forgets the Anderson history and takes other steps.
TEST(StaticChord, AContinuedChordIsOneChord) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd before = newtonAt(model, 1.0);
  const auto tangent =
      FrozenTangent::buildStatic(model, {before, Eigen::VectorXd::Zero(before.size()), 1.0});
  const StaticOptions options{1e-14, 50, 1};  // no convergence within the steps below
  StaticSolver whole(model, makeLinearSolver("cholmod"), options);
  Eigen::VectorXd uncut = before;
  ASSERT_FALSE(whole.chordSolve(model, 5.0, uncut, *tangent, 8).converged);

  StaticSolver cut(model, makeLinearSolver("cholmod"), options);
  Eigen::VectorXd x = before;
  const StaticReport first = cut.chordSolve(model, 5.0, x, *tangent, 4);
  ASSERT_EQ(first.iterations, 4);
  Eigen::VectorXd fint;
  model.internalForces(5.0, x, fint);
  Eigen::VectorXd residual;
  model.externalForces(5.0, residual);
  residual -= fint;
  model.dirichlet.zeroConstrained(residual);
  EXPECT_NEAR(first.residualNorm, residual.norm(), 1e-12 * residual.norm());
  Eigen::VectorXd restarted = x;
  const StaticReport second = cut.continueChord(model, 5.0, x, *tangent, 4);
  EXPECT_EQ(second.iterations, 4);
  EXPECT_EQ(x, uncut);

  StaticSolver fresh(model, makeLinearSolver("cholmod"), options);
  fresh.chordSolve(model, 5.0, restarted, *tangent, 4);
  EXPECT_GT((restarted - uncut).norm(), 1e-12 * (uncut - before).norm());
}

TEST(StaticChord, AStepThatInvertsAnElementThrows) {
  MechanicalModel model = chordCylinder("neohookean");
  model.loads.front().forcePerNode *= 1e4;  // far beyond what the rest tangent can take in one step
  const auto tangent = FrozenTangent::buildStatic(model, model.restState());
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd x = model.restPositions();
  EXPECT_THROW(chord.chordSolve(model, 1.0, x, *tangent, 1), InvertedElementError);
}

// The chord on threads (the analysed mean's, which has the cores to itself): the force assembly
// in fixed chunks of the tets and the float solves split into subtrees give the same iterates on
// 1, 2 or 3 threads, and the same equilibrium as the serial kernels.
TEST(StaticChord, SplitOverThreadsGivesTheSameIteratesOnAnyCount) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd before = newtonAt(model, 1.0), exact = newtonAt(model, 1.2);
  const MechanicalState at{before, Eigen::VectorXd::Zero(before.size()), 1.0};
  const auto tangent = FrozenTangent::buildStatic(model, at);
  const double moved = (exact - before).norm();
  Eigen::VectorXd first;
  int iterations = 0;
  for (int threads : {1, 2, 3, 0}) {
    StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
    Eigen::VectorXd x = before;
    const StaticReport report = chord.chordSolve(model, 1.2, x, *tangent, 30, true, threads);
    ASSERT_TRUE(report.converged) << threads;
    EXPECT_LT((x - exact).norm(), 1e-8 * moved) << threads;
    if (threads == 1) {
      first = x;
      iterations = report.iterations;
    } else if (threads > 1) {
      EXPECT_EQ((x - first).cwiseAbs().maxCoeff(), 0.0) << threads;
      EXPECT_EQ(report.iterations, iterations) << threads;
    }
  }
}

// The chunked assembly is the element loop's sum to round-off, and an inverted tet is reported
// as the loop reports it: the lowest-numbered one first, with the count of all.
TEST(ChunkedForces, EqualTheElementLoopAndReportInvertedTetsAlike) {
  const MechanicalModel model = chordCylinder("neohookean");
  const Eigen::VectorXd x = newtonAt(model, 2.0);
  Eigen::VectorXd serial, chunked1;
  model.internalForces(2.0, x, serial);
  for (int threads : {1, 2, 3}) {
    ChunkedForces chunks(threads);
    Eigen::VectorXd f;
    model.internalForces(2.0, x, f, chunks);
    EXPECT_LE((f - serial).norm(), 1e-12 * serial.norm()) << threads;
    if (threads == 1)
      chunked1 = f;
    else
      EXPECT_EQ((f - chunked1).cwiseAbs().maxCoeff(), 0.0) << threads;
  }
  // Two tets far apart in the mesh's order collapsed through their first node's opposite face.
  Eigen::VectorXd bad = model.restPositions();
  const TetMesh& mesh = *model.mesh;
  for (Eigen::Index t : {mesh.numTets() - 3, Eigen::Index(5)}) {
    const Eigen::Vector4i tet = mesh.T.row(t);
    const Vec3 centre =
        (bad.segment<3>(3 * tet(1)) + bad.segment<3>(3 * tet(2)) + bad.segment<3>(3 * tet(3))) /
        3.0;
    bad.segment<3>(3 * tet(0)) = 2.0 * centre - bad.segment<3>(3 * tet(0));
  }
  Eigen::Index element = -1, count = 0;
  try {
    model.internalForces(0.0, bad, serial);
  } catch (const InvertedElementError& e) {
    element = e.element();
    count = e.count();
  }
  ASSERT_GE(element, 0);
  for (int threads : {1, 2}) {
    ChunkedForces chunks(threads);
    Eigen::VectorXd f;
    try {
      model.internalForces(0.0, bad, f, chunks);
      ADD_FAILURE() << "no inverted tet reported on " << threads << " threads";
    } catch (const InvertedElementError& e) {
      EXPECT_EQ(e.element(), element);
      EXPECT_EQ(e.count(), count);
    }
  }
  EXPECT_THROW(ChunkedForces(0), std::invalid_argument);
}

TEST(StaticChord, AnImplicitEulerTangentIsRefused) {
  const MechanicalModel model = chordCylinder("neohookean");
  const auto tangent = FrozenTangent::build(model, model.restState(), 0.01);
  StaticSolver chord(model, makeLinearSolver("cholmod"), {1e-12, 50, 1});
  Eigen::VectorXd x = model.restPositions();
  EXPECT_THROW(chord.chordSolve(model, 1.0, x, *tangent, 1), std::invalid_argument);
}

}  // namespace
}  // namespace bcassim
