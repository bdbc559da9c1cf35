// Mean dilatation (volumetric term averaged over tet patches): the patches partition the mesh,
// affine deformations give exactly the plain element's energy and forces, forces are the energy's
// gradient and the stiffness the forces' derivative, and a nearly incompressible cantilever no
// longer locks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "FemTestHelpers.h"
#include "bcassim/Error.h"
#include "bcassim/mechanics/MeanDilatationPatches.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

namespace bcassim {
namespace {
using testing::nodesWhere;

TetMesh jitteredBox() {
  TetMesh mesh = makeBoxMesh(Vec3(0.04, 0.03, 0.03), 4, 3, 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.0015, 0.0015);
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    for (int k = 0; k < 3; ++k) mesh.V(i, k) += jitter(rng);
  return mesh;
}

Eigen::VectorXd randomDeformation(const MechanicalModel& model, double size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-size, size);
  Eigen::VectorXd x = model.restPositions();
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += u(rng);
  return x;
}

TEST(MeanDilatationPatches, PartitionTheTetsIntoCompactPatchesOfOneRegion) {
  TetMesh mesh = makeCylinderMesh(0.015, 0.18, 915);
  mesh.region.resize(mesh.numTets());
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) mesh.region(t) = mesh.V(mesh.T(t, 0), 2) < 0.09;
  for (int k : {1, 4, 8}) {
    const MeanDilatationPatches p = makeMeanDilatationPatches(mesh, k);
    std::vector<int> seen(mesh.numTets(), 0);
    int full = 0;
    for (int i = 0; i < p.numPatches(); ++i) {
      const auto& tets = p.tets[i];
      full += static_cast<int>(tets.size()) == k;
      EXPECT_LE(static_cast<int>(tets.size()), k + 1);
      ASSERT_EQ(p.local[i].size(), 4 * tets.size());
      for (size_t j = 0; j < tets.size(); ++j) {
        ++seen[tets[j]];
        EXPECT_EQ(mesh.regionOf(tets[j]), mesh.regionOf(tets[0]));
        for (int a = 0; a < 4; ++a)
          EXPECT_EQ(p.nodes[i][p.local[i][4 * j + a]], mesh.T(tets[j], a));
      }
      EXPECT_TRUE(std::is_sorted(p.nodes[i].begin(), p.nodes[i].end()));
    }
    for (int s : seen) ASSERT_EQ(s, 1);
    EXPECT_GT(full, 0.9 * p.numPatches()) << k;
    if (k == 1) {
      EXPECT_EQ(p.numPatches(), mesh.numTets());
    }
  }
  // Compact: a 4-tet patch of this prism mesh spans 7 nodes or fewer on average (a tree of 4 tets
  // joined by faces has 7; BFS-grown ones had 8).
  const MeanDilatationPatches p4 = makeMeanDilatationPatches(mesh, 4);
  double nodes = 0;
  for (const auto& n : p4.nodes) nodes += static_cast<double>(n.size());
  EXPECT_LE(nodes / p4.numPatches(), 7.0);
  EXPECT_THROW(makeMeanDilatationPatches(mesh, 0), InputError);
}

// Under x = F X + c every tet has the same theta, so the patch average changes nothing.
TEST(MeanDilatation, AffineDeformationGivesThePlainEnergyAndForces) {
  auto mesh = std::make_shared<const TetMesh>(jitteredBox());
  Mat3 F;
  F << 1.08, 0.05, -0.03, 0.02, 0.93, 0.06, -0.04, 0.03, 1.05;
  for (const char* law : {"stvk", "neohookean"}) {
    const Material m = makeMaterial(law, 8000, 0.49);
    const MechanicalModel plain = makeMechanicalModel(mesh, {m}, 1000, MassKind::Lumped);
    const MechanicalModel patched = makeMechanicalModel(mesh, {m}, 1000, MassKind::Lumped, 4);
    ASSERT_TRUE(patched.elasticity.hasMeanDilatation());
    Eigen::VectorXd x = plain.restPositions();
    for (Eigen::Index i = 0; i < mesh->numNodes(); ++i)
      x.segment<3>(3 * i) = F * mesh->V.row(i).transpose() + Vec3(0.001, -0.002, 0.003);
    const double W = plain.elasticity.energy(x);
    EXPECT_NEAR(patched.elasticity.energy(x), W, 1e-12 * std::abs(W)) << law;
    Eigen::VectorXd f0 = Eigen::VectorXd::Zero(x.size()), f1 = f0;
    plain.elasticity.addInternalForces(x, f0);
    patched.elasticity.addInternalForces(x, f1);
    EXPECT_LT((f1 - f0).norm(), 1e-11 * f0.norm()) << law;
    // A non-affine deformation does tell them apart (the test can fail).
    const Eigen::VectorXd y = randomDeformation(plain, 0.002, 5);
    EXPECT_GT(std::abs(patched.elasticity.energy(y) - plain.elasticity.energy(y)),
              1e-3 * plain.elasticity.energy(y))
        << law;
  }
}

TEST(MeanDilatation, ForcesAreTheEnergyGradientAndStiffnessTheirDerivative) {
  auto mesh = std::make_shared<const TetMesh>(jitteredBox());
  for (const char* law : {"stvk", "neohookean"}) {
    const MechanicalModel model =
        makeMechanicalModel(mesh, {makeMaterial(law, 8000, 0.49)}, 1000, MassKind::Lumped, 4);
    const Eigen::VectorXd x = randomDeformation(model, 0.002, 11);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    SparseMatrix K = model.pattern->emptyMatrix();
    model.elasticity.addForcesAndStiffness(x, *model.pattern, 1.0, f, K);
    Eigen::VectorXd fOnly = Eigen::VectorXd::Zero(x.size());
    model.elasticity.addInternalForces(x, fOnly);
    EXPECT_LT((fOnly - f).norm(), 1e-13 * f.norm()) << law;
    const Eigen::MatrixXd Kd(K);
    EXPECT_LT((Kd - Kd.transpose()).norm(), 1e-12 * Kd.norm()) << law;
    const double h = 1e-7;
    double worstF = 0, worstK = 0;
    for (int d = 0; d < x.size(); d += 7) {
      Eigen::VectorXd xp = x, xm = x;
      xp(d) += h;
      xm(d) -= h;
      const double dW = (model.elasticity.energy(xp) - model.elasticity.energy(xm)) / (2 * h);
      worstF = std::max(worstF, std::abs(dW - f(d)) / f.cwiseAbs().maxCoeff());
      Eigen::VectorXd fp = Eigen::VectorXd::Zero(x.size()), fm = fp;
      model.elasticity.addInternalForces(xp, fp);
      model.elasticity.addInternalForces(xm, fm);
      worstK = std::max(worstK, ((fp - fm) / (2 * h) - Kd.col(d)).cwiseAbs().maxCoeff() /
                                    Kd.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worstF, 1e-6) << law;
    EXPECT_LT(worstK, 1e-6) << law;
  }
}

// Tip deflection of a clamped square beam under an end load (small strain): at nu = 0.49 plain
// linear tets lock, with 4-tet patches the deflection is close to Timoshenko beam theory.
double tipDeflection(double nu, int patchTets) {
  const double L = 0.5, h = 0.1, E = 1e6, P = 0.2;
  auto mesh = std::make_shared<const TetMesh>(makeBoxMesh(Vec3(L, h, h), 15, 3, 3));
  MechanicalModel model =
      makeMechanicalModel(mesh, {makeMaterial("stvk", E, nu)}, 1000, MassKind::Lumped, patchTets);
  model.dirichlet = DirichletConditions(
      {{nodesWhere(*mesh, [](const Vec3& p) { return p.x() < 1e-12; })}}, *model.pattern);
  auto tip = nodesWhere(*mesh, [&](const Vec3& p) { return p.x() > L - 1e-12; });
  model.loads.push_back({tip, Vec3(0, 0, -P / tip.size()), {}});
  Eigen::VectorXd x = model.restPositions();
  StaticSolver solver(model, makeLinearSolver("cholmod"), {1e-8, 20, 1});
  EXPECT_TRUE(solver.solve(model, 0.0, x).converged);
  double mean = 0;
  for (int t : tip) mean += mesh->V(t, 2) - x(3 * t + 2);
  return mean / tip.size();
}

TEST(MeanDilatation, NearlyIncompressibleCantileverStopsLocking) {
  const double L = 0.5, h = 0.1, E = 1e6, P = 0.2, nu = 0.49;
  const double I = h * h * h * h / 12.0, G = E / (2 * (1 + nu)), A = h * h;
  const double theory = P * L * L * L / (3 * E * I) + P * L / (5.0 / 6.0 * G * A);
  const double plain = tipDeflection(nu, 1), patched = tipDeflection(nu, 4);
  // The plain mesh is far too stiff; the patched one is at least as close to theory as plain tets
  // at nu = 0.3 (which do not lock volumetrically) are to theirs on this coarse mesh.
  const double G3 = E / 2.6, theory3 = P * L * L * L / (3 * E * I) + P * L / (5.0 / 6.0 * G3 * A);
  const double plainAt03 = tipDeflection(0.3, 1);
  // Measured: plain 0.21 of theory at nu 0.49, 0.68 at nu 0.3 (bending, not volume, stiffens that
  // one), patched 0.72 at nu 0.49.
  EXPECT_LT(plain, 0.35 * theory) << plain << " vs " << theory;
  EXPECT_LT(patched, theory);
  EXPECT_GT(patched / theory, plainAt03 / theory3)
      << "patched " << patched / theory << ", plain at nu 0.3 " << plainAt03 / theory3;
}

TEST(MeanDilatation, RefusesMaterialsWithoutAVolumetricSplit) {
  auto mesh = std::make_shared<const TetMesh>(jitteredBox());
  try {
    makeMechanicalModel(mesh, {makeMaterial("corotational", 8000, 0.45)}, 1000, MassKind::Lumped,
                        4);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "material 'corotational' has no volumetric split for mean dilatation; expected "
                 "stvk or neohookean");
  }
}

}  // namespace
}  // namespace bcassim
