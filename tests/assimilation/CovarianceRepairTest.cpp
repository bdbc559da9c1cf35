// A covariance that lost positive definiteness is repaired with a recorded jitter and the run goes
// on; a healthy one is factorised untouched.
#include <gtest/gtest.h>

#include "assimilation/AssimilationTestModels.h"
#include "bcassim/Error.h"
#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/UkfFilter.h"

namespace bcassim {
namespace {

Eigen::MatrixXd nearlySingular() {
  // Rank 2 in 5 dimensions, then nudged indefinite by round-off-sized negative terms.
  Eigen::MatrixXd V(5, 2);
  V << 1, 0, 0.5, 1, 0.2, -0.3, 0, 0.7, 0.1, 0.1;
  return V * V.transpose() - 1e-13 * Eigen::MatrixXd::Identity(5, 5);
}

TEST(CovarianceRepair, HealthyMatrixIsUntouched) {
  std::mt19937 rng(1);
  const Eigen::MatrixXd P = testing::randomSpd(6, rng);
  RepairLog log;
  const Eigen::MatrixXd C = choleskyWithRepair(P, log);
  EXPECT_EQ(log.repairs, 0);
  EXPECT_LT((C * C.transpose() - P).norm(), 1e-13);
}

TEST(CovarianceRepair, IndefiniteMatrixGetsTheSmallestJitterThatWorks) {
  const Eigen::MatrixXd P = nearlySingular();
  RepairLog log;
  const Eigen::MatrixXd C = choleskyWithRepair(P, log);
  EXPECT_EQ(log.repairs, 1);
  EXPECT_GT(log.largestJitter, 0.0);
  EXPECT_LT(log.largestJitter, 1e-6);
  EXPECT_LT((C * C.transpose() - P).cwiseAbs().maxCoeff(), 2 * log.largestJitter);
  RepairLog nanLog;
  Eigen::MatrixXd bad = P;
  bad(0, 0) = std::nan("");
  EXPECT_THROW(choleskyWithRepair(bad, nanLog), NumericalError);
}

TEST(CovarianceRepair, UkfRepairsANearlySingularCovarianceAndCarriesOn) {
  const testing::LinearSystem s = testing::LinearSystem::make();
  testing::LinearModel model(s);
  SerialExecutor serial;
  UkfFilter ukf(StochasticState(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.1),
                                {{"a", 0.5, 0.4, {}}, {"b", 0.0, 0.3, {}}}),
                {&model}, serial);
  ukf.reset(ukf.mean(), nearlySingular());
  const auto frames = testing::linearFrames(s, Eigen::Vector2d(1.0, -0.5), 8, 0.05);
  const FilterStepReport first = ukf.step(frames[0]);
  EXPECT_GE(first.covarianceRepairs, 1);
  EXPECT_GT(first.largestJitter, 0.0);
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const FilterStepReport r = ukf.step(frames[i]);
    EXPECT_TRUE(r.mean.allFinite());
    EXPECT_TRUE(r.stddev.allFinite());
  }
}

}  // namespace
}  // namespace bcassim
