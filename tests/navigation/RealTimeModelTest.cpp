// The asynchronous mode's real-time model stepping with a frozen tangent (issue 15, point 4):
// one force assembly and one solve per frame, the stiffness of the last adopted analysis built
// on a thread of its own, against the model's own eq. 2.16 step.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "bcassim/experiments/liver/LiverScenario.h"
#include "bcassim/navigation/RealTimeModel.h"
#include "support/SmallLiverOptions.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

// The phantom liver's estimation scene (2 spring groups), coarse.
std::shared_ptr<const Scene> realTimePhantomScene() {
  return prepareLiverScenario(test::smallLiverOptions(2, 10), test::freshDir().string())
      .estimateScene;
}

double realTimeMedianMs(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Runs own and frozen side by side for `frames` frames; with `waitEachFrame` every frame waits
// for the build requested at the last one (its tangent is then that of its own start state).
struct RealTimeComparison {
  double largestMotion = 0, largestGap = 0, ownMs = 0, frozenMs = 0;
  int framesWithTangent = 0;
};

RealTimeComparison realTimeCompare(const Scene& scene, int frames, bool waitEachFrame,
                                   double periodSeconds, RealTimeModel& frozen) {
  RealTimeModel own(scene, RealTimeTangent::Own);
  RealTimeComparison r;
  std::vector<double> ownMs, frozenMs;
  auto next = std::chrono::steady_clock::now();
  for (int k = 1; k <= frames; ++k) {
    if (waitEachFrame) frozen.finishTangent();
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(periodSeconds));
    std::this_thread::sleep_until(next);
    const auto t0 = std::chrono::steady_clock::now();
    own.advanceTo(k);
    const auto t1 = std::chrono::steady_clock::now();
    frozen.advanceTo(k);
    const auto t2 = std::chrono::steady_clock::now();
    ownMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    frozenMs.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    const Eigen::MatrixX3d a = own.hiddenPositions(), b = frozen.hiddenPositions();
    EXPECT_TRUE(b.allFinite()) << "frame " << k;
    r.largestGap = std::max(r.largestGap, (a - b).rowwise().norm().maxCoeff());
    const Eigen::VectorXd motion = own.positions() - scene.model.restPositions();
    r.largestMotion = std::max(r.largestMotion,
                               motion.reshaped(3, motion.size() / 3).colwise().norm().maxCoeff());
  }
  r.ownMs = realTimeMedianMs(ownMs);
  r.frozenMs = realTimeMedianMs(frozenMs);
  r.framesWithTangent = frozen.framesWithTangent();
  return r;
}

TEST(RealTimeModel, FrozenTangentOfTheFramesOwnStateIsTheOwnStep) {
  const std::shared_ptr<const Scene> scene = realTimePhantomScene();
  RealTimeModel frozen(*scene, RealTimeTangent::Frozen, 1, 1);  // a tangent per frame
  const RealTimeComparison r = realTimeCompare(*scene, 40, true, 0, frozen);
  std::printf("tangent of each frame's own state, 40 frames: motion %.2f mm, gap %.2e mm\n",
              1e3 * r.largestMotion, 1e3 * r.largestGap);
  EXPECT_EQ(r.framesWithTangent, 40);
  EXPECT_GT(r.largestMotion, 0.002);
  // The same eq. 2.16 step (ImplicitEuler::stepWithTangent), up to the own step's iterative
  // solve (factorized PCG, relative tolerance 1e-8) and the frozen step's float factor (2e-9 of
  // the motion here; 1e-11 with the double one).
  EXPECT_LT(r.largestGap, 1e-5 * r.largestMotion);
}

// Tangents refreshed every k frames (each frame waits for its build: ages 0 .. k-1 exactly).
TEST(RealTimeModel, OlderTangentsDriftSlowlyFromTheOwnStep) {
  const std::shared_ptr<const Scene> scene = realTimePhantomScene();
  std::vector<double> gaps;
  double motion = 0;
  for (int k : {2, 4, 8}) {
    RealTimeModel own(*scene, RealTimeTangent::Own);
    RealTimeModel frozen(*scene, RealTimeTangent::Frozen, k, k);
    double gap = 0;
    for (int f = 1; f <= 150; ++f) {
      frozen.finishTangent();
      own.advanceTo(f);
      frozen.advanceTo(f);
      gap = std::max(
          gap, (own.hiddenPositions() - frozen.hiddenPositions()).rowwise().norm().maxCoeff());
      const Eigen::VectorXd m = own.positions() - scene->model.restPositions();
      motion = std::max(motion, m.reshaped(3, m.size() / 3).colwise().norm().maxCoeff());
    }
    EXPECT_EQ(frozen.framesWithTangent(), 150);
    EXPECT_EQ(frozen.tangentsAdopted(), (150 + k - 1) / k);
    gaps.push_back(gap);
    std::printf(
        "tangent refreshed every %d frames: hidden points within %.3f mm of the own step "
        "(motion %.2f mm)\n",
        k, 1e3 * gap, 1e3 * motion);
  }
  // First order in the tangent's age, and small at the serving default (refresh every 3 frames).
  EXPECT_LT(gaps[0], gaps[1]);
  EXPECT_LT(gaps[1], gaps[2]);
  EXPECT_LT(gaps[1], 0.02 * motion);
  EXPECT_LT(gaps[2], 0.06 * motion);
}

TEST(RealTimeModel, FrozenTangentsBuiltBehindTheLoopStayOnTheOwnStep) {
  const std::shared_ptr<const Scene> scene = realTimePhantomScene();
  // 150 frames (3 s of the lobes' loads) at a camera's 30 Hz, the builds running behind as in
  // `serve --async`: frames whose tangent is not young enough step with their own.
  RealTimeModel frozen(*scene, RealTimeTangent::Frozen);  // the serving defaults
  const RealTimeComparison r = realTimeCompare(*scene, 150, false, 1.0 / 30, frozen);
  std::printf(
      "tangents built behind the loop, 150 frames: motion %.2f mm, gap %.3f mm, %d frames with a "
      "frozen tangent; median step own %.2f ms, frozen %.2f ms\n",
      1e3 * r.largestMotion, 1e3 * r.largestGap, r.framesWithTangent, r.ownMs, r.frozenMs);
  EXPECT_GT(r.largestMotion, 0.005);
  // Behind the loop a tangent's age depends on the thread timing: up to 5 frames (a frame whose
  // tangent is 6 old takes its own step, unless a newer one is being built: then up to 11), so
  // the bound is that of tangents refreshed every 8 frames above, not every 4 (an idle machine
  // gives ~1 %, a loaded ctest -j2 gave 2.3 %).
  EXPECT_LT(r.largestGap, 0.06 * r.largestMotion);
}

TEST(RealTimeModel, WarmingUpLeavesTheTrajectoryAsItWas) {
  const std::shared_ptr<const Scene> scene = realTimePhantomScene();
  RealTimeModel cold(*scene, RealTimeTangent::Own);
  RealTimeModel warm(*scene, RealTimeTangent::Own);
  const Eigen::VectorXd rest = warm.positions();
  warm.warmUp();  // one own step taken and undone
  EXPECT_EQ(warm.step(), 0);
  EXPECT_EQ((warm.positions() - rest).norm(), 0.0);
  cold.advanceTo(10);
  warm.advanceTo(10);
  const double motion = (cold.positions() - rest).cwiseAbs().maxCoeff();
  EXPECT_GT(motion, 1e-4);
  // The same steps from the same state (up to the iterative solve's tolerance, 1e-8 relative).
  EXPECT_LT((warm.positions() - cold.positions()).cwiseAbs().maxCoeff(), 1e-6 * motion);
}

}  // namespace
}  // namespace bcassim
