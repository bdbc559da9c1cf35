#include "bcassim/run/ValidationErrors.h"

#include <algorithm>
#include <cmath>

namespace bcassim {

double maxDeformation(const TrackFrames& truth, const Eigen::MatrixX3d& rest) {
  const Eigen::MatrixX3d& origin =
      truth.present.empty() || !truth.present[0] ? rest : truth.frames[0];
  double d = 0.0;
  for (size_t k = 1; k < truth.frames.size(); ++k) {
    if (!truth.present[k]) continue;
    const StepError e = stepError(truth.frames[k], origin);
    d = std::max(d, e.max);
  }
  return d;
}

StepError stepError(const Eigen::MatrixX3d& model, const Eigen::MatrixX3d& truth) {
  StepError e;
  double sum = 0.0;
  for (Eigen::Index i = 0; i < truth.rows(); ++i) {
    if (!truth.row(i).allFinite() || !model.row(i).allFinite()) continue;
    const double d = (model.row(i) - truth.row(i)).norm();
    sum += d;
    e.max = std::max(e.max, d);
    ++e.points;
  }
  if (e.points) e.mean = sum / e.points;
  return e;
}

void ErrorSummary::add(const StepError& e) {
  if (e.points == 0) return;
  sum_ += e.mean * e.points;
  count_ += e.points;
  max_ = std::max(max_, e.max);
  ++steps_;
}

}  // namespace bcassim
