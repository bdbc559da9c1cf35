// Anderson acceleration (type II, depth m; Walker & Ni 2011) of a fixed-point iteration
// x <- x + f(x): each step combines the last m steps so that the residual f is least in their
// span. Applied to chord iterations (f = K0^-1 r(x) with a tangent K0 from another state), it
// makes the modes that K0 gets wrong converge as under a Krylov method instead of one chord
// factor at a time.
#pragma once
#include <Eigen/Dense>
#include <algorithm>

namespace bcassim {

class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : depth_(std::max(depth, 1)) {}

  // Forgets the history (after a step the caller had to damp, or a change of problem).
  void clear() {
    count_ = 0;
    hasLast_ = false;
  }

  // Whether the next step() combines earlier steps (false: it returns f itself).
  bool willMix() const { return hasLast_; }

  // The step to take from x, whose fixed-point residual is f (the plain f at first).
  Eigen::VectorXd step(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
    if (hasLast_) {
      if (dX_.rows() != x.size()) {
        dX_.resize(x.size(), depth_);
        dF_.resize(x.size(), depth_);
      }
      dX_.col(next_) = x - lastX_;
      dF_.col(next_) = f - lastF_;
      next_ = (next_ + 1) % depth_;
      count_ = std::min(count_ + 1, depth_);
    }
    lastX_ = x;
    lastF_ = f;
    hasLast_ = true;
    if (count_ == 0) return f;
    // The column order is irrelevant to the least-squares fit: the ring's first count_ columns.
    const auto dF = dF_.leftCols(count_);
    const Eigen::VectorXd gamma = dF.colPivHouseholderQr().solve(f);
    return f - (dX_.leftCols(count_) + dF) * gamma;
  }

 private:
  int depth_;
  int count_ = 0, next_ = 0;
  bool hasLast_ = false;
  Eigen::VectorXd lastX_, lastF_;
  Eigen::MatrixXd dX_, dF_;  // n x depth: differences of iterates and of residuals
};

}  // namespace bcassim
