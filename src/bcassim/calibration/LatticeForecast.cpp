#include "bcassim/calibration/LatticeForecast.h"

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

LatticeForecast::LatticeForecast(const SpringLattice& lattice, std::vector<double> displacements)
    : lattice_(&lattice),
      stretch_(lattice),
      displacements_(std::move(displacements)),
      reference_(lattice.restPositions()) {
  if (displacements_.empty()) throw InputError("spring lattice forecast: no frame");
}

CubicSpringCoefficients LatticeForecast::coefficients(const Eigen::VectorXd& params) {
  const double a = std::max(params(0), 0.0), g = std::max(params(2), 0.0);
  return {a, std::max(params(1), -2.0 * std::sqrt(a * g)), g};
}

Eigen::Index LatticeForecast::observableSize() const {
  return 1 + 3 * static_cast<Eigen::Index>(stretch_.freeNodes().size());
}

void LatticeForecast::observe(double reaction, const Eigen::VectorXd& x,
                              Eigen::VectorXd& observable) const {
  observable.resize(observableSize());
  observable(0) = reaction;
  const auto& nodes = stretch_.freeNodes();
  for (size_t i = 0; i < nodes.size(); ++i)
    observable.segment<3>(1 + 3 * i) = x.segment<3>(3 * nodes[i]);
}

void LatticeForecast::forecast(const Eigen::VectorXd& /*state*/, const Eigen::VectorXd& params,
                               Eigen::VectorXd& newState, Eigen::VectorXd& observable) {
  scratch_ = reference_;
  const double R = stretch_.solve(coefficients(params), displacements_[frame_], scratch_);
  newState.resize(0);
  observe(R, scratch_, observable);
}

void LatticeForecast::endStep(const Eigen::VectorXd& /*state*/, const Eigen::VectorXd& params) {
  stretch_.solve(coefficients(params), displacements_[frame_], reference_);
  if (++frame_ == static_cast<int>(displacements_.size())) {
    frame_ = 0;
    reference_ = lattice_->restPositions();
  }
}

}  // namespace bcassim
