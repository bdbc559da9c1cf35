// The model error the filter's covariance does not know about, estimated from its innovations:
// E[d_i^2] = (H P H^T)_ii + R_ii + q for each observed entry, so the mean square innovation minus
// the observation variance bounds the per-coordinate variance q of model error at the markers
// from above (H P H^T is dropped: conservative). Used to widen the hidden points' uncertainty.
#pragma once
#include <algorithm>

namespace bcassim {

class InnovationModelError {
 public:
  // One filter step: ||d|| over `entries` observed coordinates (m); steps without any are skipped.
  void add(double innovationNorm, long entries) {
    if (entries <= 0) return;
    sumSquares_ += innovationNorm * innovationNorm;
    entries_ += entries;
  }
  // q in m^2 given the observation standard deviation sigma (m): 0 until an observation came.
  double variance(double sigma) const {
    if (entries_ == 0) return 0.0;
    return std::max(0.0, sumSquares_ / static_cast<double>(entries_) - sigma * sigma);
  }

  // For checkpoints.
  double sumSquares() const { return sumSquares_; }
  long entries() const { return entries_; }
  void restore(double sumSquares, long entries) {
    sumSquares_ = sumSquares;
    entries_ = entries;
  }

 private:
  double sumSquares_ = 0.0;
  long entries_ = 0;
};

}  // namespace bcassim
