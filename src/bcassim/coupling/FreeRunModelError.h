// How the model error of a hidden point's prediction grows once observations stop: the model got
// a fraction rho of the motion wrong while it was observed (rho^2 = q / the mean squared marker
// displacement from rest per coordinate, q from InnovationModelError), so a point that moves a
// path s after the last observation gains rho^2 s^2 / 3 of variance per coordinate. Still organ,
// no growth; every step it moves, more. Metres.
#pragma once
#include <Eigen/Core>

namespace bcassim {

class FreeRunModelError {
 public:
  // After each step: whether it was observed, the displacement of the markers from rest in the
  // model following the filter's mean (one row per marker) and the hidden points' positions.
  void add(bool observed, const Eigen::MatrixX3d& markerDisplacement,
           const Eigen::MatrixX3d& hidden) {
    if (observed) {
      sumSquares_ += markerDisplacement.squaredNorm();
      entries_ += 3 * markerDisplacement.rows();
      path_ = Eigen::VectorXd::Zero(hidden.rows());
    } else if (last_.rows() == hidden.rows() && entries_ > 0) {
      path_ += (hidden - last_).rowwise().norm();
    }
    last_ = hidden;
  }

  // rho^2 for the excess innovation variance q (m^2); 0 before an observation or without motion.
  double relativeVariance(double q) const {
    const double motion = entries_ > 0 ? sumSquares_ / static_cast<double>(entries_) : 0.0;
    return motion > 0 ? q / motion : 0.0;
  }
  // Per hidden point, the variance per coordinate the free run has added so far, m^2.
  Eigen::VectorXd growth(double q) const {
    if (path_.size() == 0) return Eigen::VectorXd::Zero(last_.rows());
    return relativeVariance(q) / 3.0 * path_.array().square().matrix();
  }

  // For checkpoints.
  double sumSquares() const { return sumSquares_; }
  long entries() const { return entries_; }
  const Eigen::VectorXd& path() const { return path_; }
  const Eigen::MatrixX3d& last() const { return last_; }
  void restore(double sumSquares, long entries, Eigen::VectorXd path, Eigen::MatrixX3d last) {
    sumSquares_ = sumSquares;
    entries_ = entries;
    path_ = std::move(path);
    last_ = std::move(last);
  }

 private:
  double sumSquares_ = 0.0;
  long entries_ = 0;
  Eigen::VectorXd path_;   // per hidden point, m, since the last observed step
  Eigen::MatrixX3d last_;  // the hidden points' positions after the previous step
};

}  // namespace bcassim
