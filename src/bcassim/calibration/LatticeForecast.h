// The spring lattice as a filter sees it (assimilation/ForecastModel.h), parameter-only: the
// parameters are (k_alpha, k_beta, k_gamma); a forecast is the lattice's equilibrium at the next
// frame of the stretch, its observable the reaction on the pulled end then the free nodes'
// positions.
#pragma once
#include <vector>

#include "bcassim/assimilation/ForecastModel.h"
#include "bcassim/calibration/LatticeStretch.h"

namespace bcassim {

class LatticeForecast final : public ForecastModel {
 public:
  // displacements: the pulled end's displacement per frame (m); the frames run in order and start
  // again from the rest state after the last one (one more loading pass). The lattice must outlive
  // this object.
  LatticeForecast(const SpringLattice& lattice, std::vector<double> displacements);

  Eigen::Index stateSize() const override { return 0; }
  // 1 + 3 x free nodes: reaction (N, along y), then positions (m).
  Eigen::Index observableSize() const override;
  void forecast(const Eigen::VectorXd& state, const Eigen::VectorXd& params,
                Eigen::VectorXd& newState, Eigen::VectorXd& observable) override;
  void endStep(const Eigen::VectorXd& state, const Eigen::VectorXd& params) override;

  // Frame the next forecast solves (index into displacements).
  int frame() const { return frame_; }
  const LatticeStretch& stretch() const { return stretch_; }

  // The spring law of parameters (k_alpha, k_beta, k_gamma), made one whose force stays >= 0 for
  // every extension (a law that pushes when stretched has no stable stretch): k_alpha and k_gamma
  // at least 0, k_beta at least -2 sqrt(k_alpha k_gamma).
  static CubicSpringCoefficients coefficients(const Eigen::VectorXd& params);

 private:
  void observe(double reaction, const Eigen::VectorXd& x, Eigen::VectorXd& observable) const;

  const SpringLattice* lattice_;
  LatticeStretch stretch_;
  std::vector<double> displacements_;
  int frame_ = 0;
  Eigen::VectorXd reference_;  // the mean's equilibrium at the previous frame
  Eigen::VectorXd scratch_;
};

}  // namespace bcassim
