// Kabsch and Umeyama fits recover known rigid and similarity transforms exactly, with weights,
// and agree with Eigen's own (unweighted) Umeyama.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <random>

#include "bcassim/Error.h"
#include "bcassim/mesh/PointSetAlignment.h"

namespace bcassim {
namespace {

Eigen::MatrixX3d randomPoints(Eigen::Index rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 0.05);
  Eigen::MatrixX3d P(rows, 3);
  for (Eigen::Index i = 0; i < rows; ++i) P.row(i) << n(rng), n(rng), n(rng);
  return P;
}

SimilarityTransform knownSimilarity(double scale) {
  SimilarityTransform t;
  t.scale = scale;
  t.rotation = Eigen::AngleAxisd(2.2, Eigen::Vector3d(-1, 0.3, 2).normalized()).toRotationMatrix();
  t.translation = Eigen::Vector3d(0.12, -0.03, 0.4);
  return t;
}

TEST(PointSetAlignment, KabschRecoversARigidMotionExactly) {
  const Eigen::MatrixX3d P = randomPoints(25, 3);
  const SimilarityTransform t = knownSimilarity(1.0);
  const RigidTransform r = kabschFit(P, t.apply(P));
  EXPECT_LT((r.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((r.translation - t.translation).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_NEAR(r.rotation.determinant(), 1.0, 1e-14);
  // The same from the minimum of 3 points, and the inverse undoes it.
  const RigidTransform r3 = kabschFit(P.topRows(3), t.apply(P.topRows(3)));
  EXPECT_LT((r3.apply(P) - t.apply(P)).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((r.inverse().apply(r.apply(P)) - P).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PointSetAlignment, UmeyamaRecoversScaleRotationAndTranslation) {
  const Eigen::MatrixX3d P = randomPoints(30, 4);
  const SimilarityTransform t = knownSimilarity(1e-3);  // e.g. millimetres to metres
  const SimilarityTransform s = umeyamaFit(P, t.apply(P));
  EXPECT_NEAR(s.scale, 1e-3, 1e-16);
  EXPECT_LT((s.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((s.translation - t.translation).cwiseAbs().maxCoeff(), 1e-14);
  // Eigen's Umeyama (unweighted) finds the same transform on noisy pairs.
  const Eigen::MatrixX3d Q = t.apply(P) + 1e-4 * randomPoints(30, 5);
  const SimilarityTransform ours = umeyamaFit(P, Q);
  const Eigen::Matrix4d eigen = Eigen::umeyama(P.transpose(), Q.transpose(), true);
  EXPECT_LT((ours.scale * ours.rotation - eigen.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff(),
            1e-12);
  EXPECT_LT((ours.translation - eigen.topRightCorner<3, 1>()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PointSetAlignment, WeightsIgnoreWhatTheyZeroAndScaleNothing) {
  const Eigen::MatrixX3d P = randomPoints(20, 6);
  const SimilarityTransform t = knownSimilarity(2.5);
  Eigen::MatrixX3d Q = t.apply(P);
  Q.topRows(5) += randomPoints(5, 7);  // 5 corrupted pairs, given weight 0
  Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(20, 1.0, 3.0);
  w.head(5).setZero();
  const SimilarityTransform s = umeyamaFit(P, Q, w);
  EXPECT_NEAR(s.scale, 2.5, 1e-13);
  EXPECT_LT((s.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-12);
  const RigidTransform r = kabschFit(P, knownSimilarity(1.0).apply(P), 7.0 * w);
  EXPECT_LT((r.rotation - t.rotation).cwiseAbs().maxCoeff(), 1e-12);
  // Scaling all weights changes nothing; equal weights give the unweighted fit.
  const RigidTransform equal = kabschFit(P, Q, Eigen::VectorXd::Constant(20, 0.3));
  const RigidTransform unweighted = kabschFit(P, Q);
  EXPECT_LT((equal.rotation - unweighted.rotation).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((equal.translation - unweighted.translation).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(PointSetAlignment, ReflectedPointsStillGiveARotation) {
  const Eigen::MatrixX3d P = randomPoints(10, 8);
  Eigen::MatrixX3d Q = P;
  Q.col(2) *= -1.0;  // a mirror image: no rotation maps P onto it
  EXPECT_NEAR(kabschFit(P, Q).rotation.determinant(), 1.0, 1e-14);
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(PointSetAlignment, BadInputsAreOneLineErrors) {
  const Eigen::MatrixX3d P = randomPoints(4, 9);
  EXPECT_EQ(errorOf([&] { kabschFit(P, P.topRows(3)); }),
            "Kabsch: point sets of 4 and 3 rows; expected two paired sets of >= 3 points");
  EXPECT_EQ(errorOf([&] { umeyamaFit(P, P, Eigen::VectorXd::Ones(3)); }),
            "Umeyama: 3 weights for 4 points; expected one weight per point");
  EXPECT_EQ(errorOf([&] { kabschFit(P, P, Eigen::Vector4d(1, -1, 1, 1)); }),
            "Kabsch: weight 1 is -1; expected a finite number >= 0");
  EXPECT_EQ(errorOf([&] { kabschFit(P, P, Eigen::Vector4d::Zero()); }),
            "Kabsch: all weights are 0; expected a positive sum");
  EXPECT_EQ(errorOf([&] { umeyamaFit(Eigen::MatrixX3d::Ones(4, 3), P); }),
            "Umeyama: the weighted source points all coincide; expected points spread in space "
            "to fit a scale");
}

}  // namespace
}  // namespace bcassim
