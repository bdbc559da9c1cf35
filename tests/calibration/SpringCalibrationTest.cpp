// Spring coefficients from a FEM membrane (thesis §2.3.4): the lattice has 6 edge and 12 diagonal
// springs around an inner node, its forces and stiffness are the derivatives of its energy, its
// stretch reaches equilibrium; at small size the springs estimated by ROUKF reproduce the
// membrane's reaction within 5 %; `ligament springs` refuses bad input in one line.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "bcassim/calibration/LatticeStretch.h"
#include "bcassim/calibration/SpringCalibration.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

TEST(SpringLattice, AnInnerNodeHasSixEdgeAndTwelveDiagonalSprings) {
  const SpringLattice lattice(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  const int centre = lattice.node(1, 1, 1);
  int edges = 0, diagonals = 0;
  for (const LatticeSpring& s : lattice.springs())
    if (s.a == centre || s.b == centre) ++(s.diagonal ? diagonals : edges);
  EXPECT_EQ(edges, 6);
  EXPECT_EQ(diagonals, 12);
  // Per cell: 12 edges (shared) and 2 diagonals on each of its 6 faces (shared).
  const SpringLattice one(Vec3(0.01, 0.01, 0.01), 1, 1, 1);
  EXPECT_EQ(one.springs().size(), 24u);
}

TEST(SpringLattice, ForcesAndStiffnessAreTheEnergysDerivatives) {
  const SpringLattice lattice(Vec3(0.04, 0.1, 0.001), 2, 3, 1);
  const CubicSpringCoefficients k{3e5, -2e3, 40};
  Eigen::VectorXd x = lattice.restPositions();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += u(rng) + (i % 3 == 1 ? 0.2 * x(i) : 0.0);
  Eigen::VectorXd f;
  std::vector<Eigen::Triplet<double>> triplets;
  lattice.forces(x, k, f, &triplets);
  SparseMatrix K(x.size(), x.size());
  K.setFromTriplets(triplets.begin(), triplets.end());
  const double h = 1e-7;
  double worstF = 0, worstK = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x, fp, fm;
    xp(i) += h;
    xm(i) -= h;
    worstF = std::max(worstF,
                      std::abs((lattice.energy(xp, k) - lattice.energy(xm, k)) / (2 * h) - f(i)));
    lattice.forces(xp, k, fp);
    lattice.forces(xm, k, fm);
    worstK =
        std::max(worstK, ((fp - fm) / (2 * h) - Eigen::VectorXd(K.col(i))).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worstF, 1e-6 * f.cwiseAbs().maxCoeff());
  EXPECT_LT(worstK, 1e-5 * Eigen::MatrixXd(K).cwiseAbs().maxCoeff());
}

TEST(SpringLattice, StretchReachesEquilibriumAndTheReactionGrows) {
  const SpringLattice lattice(Vec3(0.04, 0.1, 0.001), 4, 10, 1);
  LatticeStretch stretch(lattice);
  const CubicSpringCoefficients k{1e4, 0, 50};
  Eigen::VectorXd x = lattice.restPositions();
  double previous = 0;
  for (double d : {0.01, 0.02, 0.04}) {
    const double R = stretch.solve(k, d, x);
    EXPECT_GT(R, previous);
    previous = R;
    Eigen::VectorXd f;
    lattice.forces(x, k, f);
    for (int p : stretch.freeNodes()) EXPECT_LT(f.segment<3>(3 * p).norm(), 1e-8 * R);
    for (int p : stretch.pulledNodes())
      EXPECT_NEAR(x(3 * p + 1), lattice.restPositions()(3 * p + 1) + d, 1e-15);
  }
}

// The small membrane of the ctest suite: 8 x 20 x 1 hexahedra (960 tets), a 4 x 10 lattice.
SpringCalibrationOptions smallMembrane(double young) {
  SpringCalibrationOptions o;
  o.membrane.young = young;
  o.membrane.cellsX = 8;
  o.membrane.cellsY = 20;
  o.strain = 0.45;  // 9 frames of 5 %, 5 passes: the defaults
  return o;
}

TEST(SpringCalibration, EstimatedSpringsReproduceTheMembranesReactionWithinFivePercent) {
  const SpringCalibrationResult soft = calibrateSprings(smallMembrane(403e3));
  ASSERT_EQ(soft.frames.size(), 9u);
  for (const SpringFrame& f : soft.frames) {
    EXPECT_GT(f.membraneReaction, 0);
    EXPECT_NEAR(f.latticeReaction, f.membraneReaction, 0.05 * f.membraneReaction)
        << "strain " << f.strain;
  }
  EXPECT_LT(soft.maxReactionError, 0.05);
  // The filter did the work: its start (least squares at the membrane's positions) is further off.
  const SpringLattice lattice(Vec3(0.04, 0.1, 0.001), 4, 10, 1);
  LatticeStretch start(lattice);
  Eigen::VectorXd x = lattice.restPositions();
  double startError = 0;
  for (const SpringFrame& f : soft.frames)
    startError = std::max(
        startError, std::abs(start.solve(soft.initial, f.displacement, x) - f.membraneReaction) /
                        f.membraneReaction);
  EXPECT_GT(startError, 2 * soft.maxReactionError);
  // Under the membrane's force the attachment follows the membrane's (thesis: max < 4 mm).
  EXPECT_LT(soft.attachmentMaxError, 1e-3);
  EXPECT_GT(soft.stddev.minCoeff(), 0);
  // A stiffer membrane of the same law: the reaction and so the coefficients scale with E.
  const SpringCalibrationResult stiff = calibrateSprings(smallMembrane(72e6));
  EXPECT_LT(stiff.maxReactionError, 0.05);
  const double ratio = 72e6 / 403e3;
  EXPECT_NEAR(stiff.estimated.kGamma / soft.estimated.kGamma, ratio, 1e-3 * ratio);
  EXPECT_NEAR(stiff.perMetre[2].mean / soft.perMetre[2].mean, ratio, 1e-3 * ratio);
  // Neo-Hookean's nominal stress softens: the free fit's K_beta < 0, the scene-ready one's >= 0.
  EXPECT_LT(soft.perMetre[1].mean, 0);
  for (const CoefficientPrior& p : soft.perMetreNonNegative) EXPECT_GE(p.mean, 0);
}

TEST(LigamentSpringsCli, BadInputIsOneLine) {
  const auto dir = test::freshDir();
  const std::string geometry = " --width 0.04 --length 0.1";
  const test::CliResult negative =
      test::runBcassim(dir, "ligament springs --young 403e3 --thickness -1e-3" + geometry);
  EXPECT_EQ(negative.exitCode, 2);
  EXPECT_EQ(
      negative.err,
      "bcassim: error: --thickness: expected a number > 0, got '-1e-3' (see 'bcassim --help')\n");
  const test::CliResult missing =
      test::runBcassim(dir, "ligament springs --young 403e3 --thickness 1e-3 --length 0.1");
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_EQ(missing.err, "bcassim: error: --width is required (see 'bcassim --help')\n");
  const test::CliResult noYoung =
      test::runBcassim(dir, "ligament springs --thickness 1e-3" + geometry);
  EXPECT_EQ(noYoung.exitCode, 2);
  EXPECT_EQ(noYoung.err,
            "bcassim: error: --young or --fit: the membrane's Young's modulus is required\n");
}

}  // namespace
}  // namespace bcassim
