// Ensemble transform Kalman filter (thesis Alg. 3, eq. 3.13-3.18; Hunt et al. 2007) with additive
// inflation: N members forecast in parallel, analysed in the N-dimensional ensemble space.
#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "bcassim/assimilation/Filter.h"
#include "bcassim/assimilation/FilterOptions.h"
#include "bcassim/assimilation/ForecastEnsemble.h"

namespace bcassim {

struct EtkfOptions : FilterOptions {
  int members = 10;        // N >= 2
  std::uint64_t seed = 1;  // std::mt19937_64: the same seed gives the same run
  // Additive inflation (Alg. 3 line 18): after each forecast every member's perturbation gets a
  // draw of N(0, diag(processVariance)) (unconstrained space); empty = none. The draws are centred
  // over the members so that inflation widens the ensemble without moving its mean. With a
  // parameter-only state the members get it before their forecast (the step's observations
  // depend on the parameters directly: a random walk).
  Eigen::VectorXd processVariance;
};

class EtkfFilter final : public Filter {
 public:
  // Members start as mean + diag(sigma) * N(0, 1) draws from the layout's initial statistics.
  EtkfFilter(StochasticState layout, std::vector<ForecastModel*> models, Executor& executor,
             EtkfOptions options = {});

  FilterStepReport step(const Observation& y) override;
  const Eigen::VectorXd& mean() const override { return x_; }
  // Sample covariance of the members, X' X'^T / (N - 1).
  Eigen::MatrixXd covariance() const override;
  Eigen::MatrixXd covarianceFactor() const override;
  FilterState saveState() const override;
  void restoreState(const FilterState& state) override;  // anomalies / sqrt(N - 1), n x N

  const Eigen::MatrixXd& members() const { return members_; }  // n x N
  // Replaces the ensemble (restoring a checkpoint); the mean becomes its column mean.
  void reset(Eigen::MatrixXd members);

 private:
  ForecastEnsemble ensemble_;
  EtkfOptions options_;
  std::mt19937_64 rng_;
  Eigen::MatrixXd members_;
  Eigen::VectorXd x_;
};

}  // namespace bcassim
