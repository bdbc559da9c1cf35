// The thesis' validation metric (§3.4): distances between model and truth positions of the
// validation points, averaged and maximised over points and steps, in m and relative to the
// truth's maximal deformation D = max over points and steps of |p_truth(t) - p_truth(0)|.
#pragma once
#include <Eigen/Core>
#include <array>

#include "bcassim/scene/AssimilationSettings.h"

namespace bcassim {

// D of `truth` over its frames 1 .. steps, displacements from its frame 0, or from `rest` when
// the file has no frame at t = 0. Points missing in a frame are skipped.
double maxDeformation(const TrackFrames& truth, const Eigen::MatrixX3d& rest);

// Error of one step over the points the truth has in that frame.
struct StepError {
  double mean = 0.0;  // m
  double max = 0.0;   // m
  int points = 0;     // 0: no truth this step
};

StepError stepError(const Eigen::MatrixX3d& model, const Eigen::MatrixX3d& truth);

// Accumulates step errors: the mean is over every (point, step) pair, the max over all of them.
class ErrorSummary {
 public:
  void add(const StepError& e);
  int steps() const { return steps_; }
  double meanM() const { return count_ ? sum_ / count_ : 0.0; }
  double maxM() const { return max_; }
  // For checkpoints: the accumulators (sum, max, count, steps), and back.
  std::array<double, 4> saved() const {
    return {sum_, max_, static_cast<double>(count_), static_cast<double>(steps_)};
  }
  void restore(const std::array<double, 4>& a) {
    sum_ = a[0];
    max_ = a[1];
    count_ = static_cast<long>(a[2]);
    steps_ = static_cast<int>(a[3]);
  }

 private:
  double sum_ = 0.0, max_ = 0.0;
  long count_ = 0;
  int steps_ = 0;
};

}  // namespace bcassim
