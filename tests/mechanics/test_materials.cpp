// Material laws against finite differences, closed-form uniaxial values, the linear limit at F = I
// and frame indifference.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "bcassim/mechanics/materials/Material.h"

namespace bcassim {
namespace {

constexpr double kE = 1.0e4;  // Pa, liver-like
constexpr double kNu = 0.45;

struct Case {
  std::string label;
  Mat3 F;
};

Mat3 randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// Deformations exercised by every check: rest, rigid motion, compression, stretch, shear,
// repeated and nearly repeated stretches, random ones. Inverted ones only where the law allows.
std::vector<Case> deformations(bool withInverted) {
  std::mt19937 rng(20240611);
  auto rotated = [&](const Vec3& stretches) {
    return Mat3(randomRotation(rng) * stretches.asDiagonal() * randomRotation(rng));
  };
  std::vector<Case> cases = {
      {"identity", Mat3::Identity()},
      {"rotation", randomRotation(rng)},
      {"compression", rotated(Vec3(0.7, 0.8, 0.9))},
      {"strong compression", rotated(Vec3(0.3, 0.5, 0.6))},
      {"stretch", rotated(Vec3(1.4, 1.1, 1.2))},
      {"uniaxial diag(a,b,b)", Vec3(1.3, 0.9, 0.9).asDiagonal().toDenseMatrix()},
      {"uniaxial compression", Vec3(0.8, 1.1, 1.1).asDiagonal().toDenseMatrix()},
      {"repeated stretch rotated", rotated(Vec3(1.2, 1.2, 0.8))},
      {"nearly repeated stretch", rotated(Vec3(1.1, 1.1 + 1e-9, 0.95))},
      {"rotation times small strain", rotated(Vec3(1.0 + 1e-3, 1.0 - 2e-3, 1.0))},
  };
  Mat3 shear = Mat3::Identity();
  shear(0, 1) = 0.5;
  cases.push_back({"simple shear", shear});
  std::normal_distribution<double> n;
  for (int k = 0; cases.size() < 22; ++k) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 9; ++i) F(i) += 0.3 * n(rng);
    if (F.determinant() > 0.3) cases.push_back({"random " + std::to_string(k), F});
  }
  if (withInverted) cases.push_back({"inverted", rotated(Vec3(1.2, 0.9, -0.3))});
  return cases;
}

double relErr(const auto& value, const auto& reference, double floor) {
  return (value - reference).norm() / std::max(reference.norm(), floor);
}

// Energy differences cancel more digits than stress differences (near a stress-free state the
// energy is flat), so the stress check uses a wider step with the fourth-order central stencil.
template <class M>
Mat3 fdStress(const M& m, const Mat3& F, double h) {
  Mat3 P;
  for (int i = 0; i < 9; ++i) {
    auto psi = [&](double t) {
      Mat3 G = F;
      G(i) += t;
      return m.energy(G);
    };
    P(i) = (8 * (psi(h) - psi(-h)) - (psi(2 * h) - psi(-2 * h))) / (12 * h);
  }
  return P;
}

template <class M>
Mat9 fdTangent(const M& m, const Mat3& F, double h) {
  Mat9 C;
  for (int j = 0; j < 9; ++j) {
    Mat3 Fp = F, Fm = F;
    Fp(j) += h;
    Fm(j) -= h;
    const Mat3 dP = (m.pk1(Fp) - m.pk1(Fm)) / (2 * h);
    C.col(j) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data());
  }
  return C;
}

// C(i + 3j, k + 3l) = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk), written out independently.
Mat9 isotropicElasticity(double lambda, double mu) {
  Mat9 C;
  auto d = [](int a, int b) { return a == b ? 1.0 : 0.0; };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          C(i + 3 * j, k + 3 * l) =
              lambda * d(i, j) * d(k, l) + mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k));
  return C;
}

template <class M>
class AllMaterials : public ::testing::Test {};
template <class M>
class NonlinearMaterials : public ::testing::Test {};
using AllTypes = ::testing::Types<LinearMaterial, CorotationalMaterial, StvkMaterial,
                                  NeoHookeanMaterial, MooneyRivlinMaterial, OgdenMaterial>;
using NonlinearTypes = ::testing::Types<CorotationalMaterial, StvkMaterial, NeoHookeanMaterial,
                                        MooneyRivlinMaterial, OgdenMaterial>;
TYPED_TEST_SUITE(AllMaterials, AllTypes);
TYPED_TEST_SUITE(NonlinearMaterials, NonlinearTypes);

template <class M>
constexpr bool kDefinedWhenInverted =
    std::is_same_v<M, LinearMaterial> || std::is_same_v<M, CorotationalMaterial> ||
    std::is_same_v<M, StvkMaterial>;

// Runs the FD checks on one material instance; returns the worst errors seen.
template <class M>
std::pair<double, double> checkAgainstFiniteDifferences(const M& m, double stressScale) {
  double worstP = 0, worstC = 0;
  for (const auto& [label, F] : deformations(kDefinedWhenInverted<M>)) {
    SCOPED_TRACE(std::string(M::name()) + " at " + label);
    const Mat3 P = m.pk1(F);
    const Mat9 C = m.tangent(F);
    // The floor only matters at stress-free states, where a relative error is meaningless.
    const double eP = relErr(P, fdStress(m, F, 1e-4 * F.norm()), 1e-3 * stressScale);
    const double eC = relErr(C, fdTangent(m, F, 1e-6 * F.norm()), 1e-3 * stressScale);
    EXPECT_LT(eP, 1e-6);
    EXPECT_LT(eC, 1e-6);
    worstP = std::max(worstP, eP);
    worstC = std::max(worstC, eC);

    Mat3 P2;
    Mat9 C2;
    m.pk1AndTangent(F, P2, C2);
    EXPECT_LE(relErr(P2, P, stressScale), 1e-14);
    EXPECT_LE(relErr(C2, C, stressScale), 1e-14);
    EXPECT_LE((C - C.transpose()).norm(), 1e-12 * C.norm()) << "major symmetry";
  }
  return {worstP, worstC};
}

TYPED_TEST(AllMaterials, StressAndTangentMatchFiniteDifferences) {
  const auto [eP, eC] = checkAgainstFiniteDifferences(TypeParam::fromYoungPoisson(kE, kNu), kE);
  std::cout << "[ worst FD ] " << TypeParam::name() << ": pk1 " << eP << ", tangent " << eC
            << std::endl;
}

TYPED_TEST(AllMaterials, NearlyIncompressibleMatchesFiniteDifferences) {
  const auto [eP, eC] = checkAgainstFiniteDifferences(TypeParam::fromYoungPoisson(kE, 0.49), kE);
  std::cout << "[ worst FD ] " << TypeParam::name() << " (nu 0.49): pk1 " << eP << ", tangent "
            << eC << std::endl;
}

TEST(OgdenMaterial, ThesisLiverAndOtherExponentsMatchFiniteDifferences) {
  for (const OgdenMaterial& m :
       {OgdenMaterial::liver(), OgdenMaterial::fromYoungPoisson(kE, kNu, 2.0),
        OgdenMaterial::fromYoungPoisson(kE, kNu, -1.5),
        OgdenMaterial::fromYoungPoisson(kE, kNu, 8.0)}) {
    SCOPED_TRACE("alpha " + std::to_string(m.alpha));
    checkAgainstFiniteDifferences(m, m.mu);
  }
}

TEST(MooneyRivlinMaterial, ThesisParametersMatchFiniteDifferences) {
  const auto m = MooneyRivlinMaterial::thesis();
  checkAgainstFiniteDifferences(m, m.c10);
}

TYPED_TEST(AllMaterials, RestStateIsStressFreeWithLinearElasticTangent) {
  const auto m = TypeParam::fromYoungPoisson(kE, kNu);
  const Mat3 I = Mat3::Identity();
  EXPECT_NEAR(m.energy(I), 0.0, 1e-12 * kE);
  EXPECT_LE(m.pk1(I).norm(), 1e-12 * kE);
  const auto lame = LameParameters::fromYoungPoisson(kE, kNu);
  const Mat9 expected = isotropicElasticity(lame.lambda, lame.mu);
  EXPECT_LE(relErr(m.tangent(I), expected, 0.0), 1e-12);
}

TYPED_TEST(NonlinearMaterials, RigidRotationIsStressFree) {
  const auto m = TypeParam::fromYoungPoisson(kE, kNu);
  std::mt19937 rng(7);
  for (int k = 0; k < 5; ++k) {
    const Mat3 Q = randomRotation(rng);
    EXPECT_NEAR(m.energy(Q), 0.0, 1e-11 * kE);
    EXPECT_LE(m.pk1(Q).norm(), 1e-11 * kE);
  }
}

TYPED_TEST(NonlinearMaterials, FrameIndifferent) {
  const auto m = TypeParam::fromYoungPoisson(kE, kNu);
  std::mt19937 rng(11);
  for (const auto& [label, F] : deformations(false)) {
    SCOPED_TRACE(label);
    const Mat3 Q = randomRotation(rng);
    const double psi = m.energy(F);
    EXPECT_NEAR(m.energy(Q * F), psi, 1e-10 * std::max(std::abs(psi), kE * 1e-3));
    EXPECT_LE(relErr(m.pk1(Q * F), Mat3(Q * m.pk1(F)), kE * 1e-3), 1e-10);
  }
}

// F = diag(a, b, b): each P_ii below is d Psi / d F_ii derived by hand from the energy.
struct UniaxialStretch {
  double a, b;
};
constexpr UniaxialStretch kUniaxialStretches[] = {
    {1.3, 0.9}, {0.7, 1.15}, {1.05, 1.05}, {2.0, 0.6}};

Mat3 diagAbb(const UniaxialStretch& u) { return Vec3(u.a, u.b, u.b).asDiagonal(); }

void expectDiagonalStress(const Mat3& P, double p11, double p22) {
  EXPECT_NEAR(P(0, 0), p11, 1e-12 * std::abs(p11));
  EXPECT_NEAR(P(1, 1), p22, 1e-12 * std::abs(p22));
  EXPECT_NEAR(P(2, 2), p22, 1e-12 * std::abs(p22));
  EXPECT_LE((P - Mat3(P.diagonal().asDiagonal())).norm(), 1e-12 * P.norm());
}

TEST(UniaxialClosedForm, Linear) {
  const auto m = LinearMaterial::fromYoungPoisson(kE, kNu);
  for (auto [a, b] : kUniaxialStretches) {
    const double tr = a + 2 * b - 3;
    expectDiagonalStress(m.pk1(diagAbb({a, b})), 2 * m.mu * (a - 1) + m.lambda * tr,
                         2 * m.mu * (b - 1) + m.lambda * tr);
  }
}

TEST(UniaxialClosedForm, Corotational) {
  const auto m = CorotationalMaterial::fromYoungPoisson(kE, kNu);
  for (auto [a, b] : kUniaxialStretches) {
    const double tr = a + 2 * b - 3;
    expectDiagonalStress(m.pk1(diagAbb({a, b})), 2 * m.mu * (a - 1) + m.lambda * tr,
                         2 * m.mu * (b - 1) + m.lambda * tr);
  }
}

TEST(UniaxialClosedForm, Stvk) {
  const auto m = StvkMaterial::fromYoungPoisson(kE, kNu);
  for (auto [a, b] : kUniaxialStretches) {
    const double trE = (a * a + 2 * b * b - 3) / 2;
    expectDiagonalStress(m.pk1(diagAbb({a, b})), a * (m.lambda * trE + m.mu * (a * a - 1)),
                         b * (m.lambda * trE + m.mu * (b * b - 1)));
  }
}

TEST(UniaxialClosedForm, NeoHookean) {
  const auto m = NeoHookeanMaterial::fromYoungPoisson(kE, kNu);
  for (auto [a, b] : kUniaxialStretches) {
    const double lnJ = std::log(a * b * b);
    expectDiagonalStress(m.pk1(diagAbb({a, b})), m.mu * (a - 1 / a) + m.lambda * lnJ / a,
                         m.mu * (b - 1 / b) + m.lambda * lnJ / b);
  }
}

TEST(UniaxialClosedForm, MooneyRivlin) {
  const auto m = MooneyRivlinMaterial::fromYoungPoisson(kE, kNu);
  for (auto [a, b] : kUniaxialStretches) {
    const double J = a * b * b, I1 = a * a + 2 * b * b, I2 = 2 * a * a * b * b + b * b * b * b;
    const double j23 = std::pow(J, -2.0 / 3), j43 = std::pow(J, -4.0 / 3);
    const double p11 = m.c10 * j23 * (2 * a - 2 * I1 / (3 * a)) +
                       m.c01 * j43 * (4 * a * b * b - 4 * I2 / (3 * a)) + m.kappa * (J - 1) * b * b;
    const double p22 = m.c10 * j23 * (2 * b - 2 * I1 / (3 * b)) +
                       m.c01 * j43 * (2 * b * (a * a + b * b) - 4 * I2 / (3 * b)) +
                       m.kappa * (J - 1) * a * b;
    expectDiagonalStress(m.pk1(diagAbb({a, b})), p11, p22);
  }
}

TEST(UniaxialClosedForm, Ogden) {
  for (const auto& m : {OgdenMaterial::liver(), OgdenMaterial::fromYoungPoisson(kE, kNu, 3.0)}) {
    for (auto [a, b] : kUniaxialStretches) {
      const double J = a * b * b, al = m.alpha, s = std::pow(a, al) + 2 * std::pow(b, al);
      const double c = 2 * m.mu / al * std::pow(J, -al / 3);
      const double p11 = (c * (std::pow(a, al) - s / 3) + m.kappa * (J - 1) * J) / a;
      const double p22 = (c * (std::pow(b, al) - s / 3) + m.kappa * (J - 1) * J) / b;
      expectDiagonalStress(m.pk1(diagAbb({a, b})), p11, p22);
      const double psi =
          2 * m.mu / (al * al) * (s * std::pow(J, -al / 3) - 3) + m.kappa / 2 * (J - 1) * (J - 1);
      EXPECT_NEAR(m.energy(diagAbb({a, b})), psi, 1e-12 * std::abs(psi));
    }
  }
}

TEST(CorotationalMaterial, StressMatchesPolarDecompositionFormula) {
  const auto m = CorotationalMaterial::fromYoungPoisson(kE, kNu);
  for (const auto& [label, F] : deformations(false)) {
    SCOPED_TRACE(label);
    // R = F (F^T F)^(-1/2), computed independently of the material's SVD.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(F.transpose() * F);
    const Mat3 R = F * eig.operatorInverseSqrt();
    const Mat3 P =
        2 * m.mu * (F - R) + m.lambda * (R.transpose() * F - Mat3::Identity()).trace() * R;
    EXPECT_LE(relErr(m.pk1(F), P, kE * 1e-3), 1e-9);
  }
}

TEST(CorotationalMaterial, InvertedElementGetsRotationNotReflection) {
  const auto m = CorotationalMaterial::fromYoungPoisson(kE, kNu);
  // F = R diag(1, 1, -0.5): the polar factor is the identity, not the reflection diag(1, 1, -1).
  const Mat3 F = Vec3(1.0, 1.0, -0.5).asDiagonal();
  const double tr = 1.0 + 1.0 - 0.5 - 3.0;
  const Mat3 expected =
      Vec3(m.lambda * tr, m.lambda * tr, 2 * m.mu * -1.5 + m.lambda * tr).asDiagonal();
  EXPECT_LE(relErr(m.pk1(F), expected, 0.0), 1e-12);
  EXPECT_TRUE(m.tangent(Mat3::Zero()).allFinite());
}

TEST(RotationVariantSvd, ReconstructsWithRotationsForEveryKindOfF) {
  std::mt19937 rng(3);
  std::vector<std::pair<Vec3, bool>> spectra = {
      {Vec3(1, 1, 1), false},     {Vec3(2, 1, 0.5), false},     {Vec3(1.5, 1.5, 0.3), false},
      {Vec3(2, 0.4, 0.4), false}, {Vec3(1, 1e-3, 1e-6), false}, {Vec3(1.2, 0.9, -0.3), false},
      {Vec3(1, 1, -1), false},    {Vec3(1, 0.5, 0), false},     {Vec3(1, 0, 0), false},
      {Vec3(0, 0, 0), false},     {Vec3(3, 1, 1), true}};
  std::normal_distribution<double> n;
  for (int k = 0; k < 20; ++k) spectra.push_back({Vec3(n(rng), n(rng), n(rng)), true});
  for (const auto& [spectrum, dense] : spectra) {
    Mat3 F;
    if (dense) {
      F = Mat3::Identity() + 0.5 * Mat3::NullaryExpr([&] { return n(rng); });
    } else {
      F = randomRotation(rng) * spectrum.asDiagonal() * randomRotation(rng).transpose();
    }
    SCOPED_TRACE(::testing::Message() << "F =\n" << F);
    const auto r = detail::rotationVariantSvd(F);
    EXPECT_LE((r.U * r.sigma.asDiagonal() * r.V.transpose() - F).norm(), 1e-14 * (1 + F.norm()));
    EXPECT_LE((r.U.transpose() * r.U - Mat3::Identity()).norm(), 1e-14);
    EXPECT_LE((r.V.transpose() * r.V - Mat3::Identity()).norm(), 1e-14);
    EXPECT_NEAR(r.U.determinant(), 1.0, 1e-14);
    EXPECT_NEAR(r.V.determinant(), 1.0, 1e-14);
    EXPECT_GE(r.sigma(0), r.sigma(1) * (1 - 1e-14));
    EXPECT_GE(r.sigma(1), std::abs(r.sigma(2)) * (1 - 1e-14));
    // sigma_3 carries the sign of det F, which roundoff decides for a singular F (rank 1 or 2).
    if (std::abs(F.determinant()) > 1e-13 * std::pow(F.norm(), 3)) {
      EXPECT_GE(r.sigma(2) * F.determinant(), 0.0);
    }
    if (!dense) {
      // Small singular values keep their relative accuracy (graded case 1, 1e-3, 1e-6).
      Vec3 expected = spectrum.cwiseAbs();
      std::sort(expected.data(), expected.data() + 3, std::greater<>());
      if (spectrum.prod() < 0) expected(2) = -expected(2);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(r.sigma(i), expected(i), 1e-13 * std::abs(expected(i)) + 1e-15);
    }
  }
}

TEST(MaterialDomain, AdmissibleFlagsInvertedElementsForLogAndPowerLaws) {
  const Mat3 inverted = Vec3(1.0, 1.0, -0.5).asDiagonal();
  EXPECT_FALSE(NeoHookeanMaterial::admissible(inverted));
  EXPECT_FALSE(MooneyRivlinMaterial::admissible(inverted));
  EXPECT_FALSE(OgdenMaterial::admissible(inverted));
  EXPECT_FALSE(NeoHookeanMaterial::admissible(Mat3::Zero()));
  EXPECT_TRUE(NeoHookeanMaterial::admissible(Mat3::Identity()));
  EXPECT_TRUE(LinearMaterial::admissible(inverted));
  EXPECT_TRUE(CorotationalMaterial::admissible(inverted));
  EXPECT_TRUE(StvkMaterial::admissible(inverted));
  EXPECT_FALSE(std::isfinite(NeoHookeanMaterial::fromYoungPoisson(kE, kNu).energy(inverted)));
}

TEST(MaterialParameters, ThesisValuesAndMappedModuli) {
  const auto mr = MooneyRivlinMaterial::thesis();
  EXPECT_EQ(mr.c10, 0.2112e6);
  EXPECT_EQ(mr.c01, 0.0617e6);
  const double muMr = 2 * (mr.c10 + mr.c01);
  EXPECT_NEAR((3 * mr.kappa - 2 * muMr) / (2 * (3 * mr.kappa + muMr)), 0.49, 1e-12);

  const auto og = OgdenMaterial::liver();
  EXPECT_EQ(og.mu, 16.47e3);
  EXPECT_EQ(og.alpha, 0.88);
  EXPECT_NEAR((3 * og.kappa - 2 * og.mu) / (2 * (3 * og.kappa + og.mu)), 0.49, 1e-12);

  const auto mrE = MooneyRivlinMaterial::fromYoungPoisson(kE, kNu);
  EXPECT_NEAR(mrE.c01 / mrE.c10, 0.0617 / 0.2112, 1e-12);
}

TEST(MakeMaterial, BuildsEveryNamedLaw) {
  for (const char* name :
       {"linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"}) {
    const Material m = makeMaterial(name, kE, kNu);
    EXPECT_STREQ(materialName(m), name);
  }
  const auto nh = std::get<NeoHookeanMaterial>(makeMaterial("neohookean", kE, kNu));
  const auto lame = LameParameters::fromYoungPoisson(kE, kNu);
  EXPECT_EQ(nh.lambda, lame.lambda);
  EXPECT_EQ(nh.mu, lame.mu);
}

TEST(MakeMaterial, RejectsUnknownNamesAndBadModuli) {
  try {
    makeMaterial("rubber", kE, kNu);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "unknown material 'rubber'; expected one of linear, corotational, stvk, "
                 "neohookean, mooneyrivlin, ogden");
  }
  EXPECT_THROW(makeMaterial("ogden", kE, 0.5), InputError);
  EXPECT_THROW(makeMaterial("stvk", -1.0, 0.3), InputError);
  EXPECT_THROW(makeMaterial("stvk", std::nan(""), 0.3), InputError);
}

}  // namespace
}  // namespace bcassim
