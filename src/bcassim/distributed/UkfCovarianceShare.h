// One rank's part in a full-state UKF step whose covariance is kept over the ranks
// (BlockCyclicCovariance): it forms its own block of sigma points from the factor's columns it is
// handed, keeps its forecasts, adds their Gram matrix into the pieces and the Kalman update into
// its piece. Rank 0 (MpiUkfCovariance) and the worker ranks (MpiForecastServer) call the same
// collective methods, so that the steps cannot drift apart; only vectors and m x s matrices
// (m observations) meet on rank 0.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/SigmaPointSet.h"
#include "bcassim/distributed/BlockCyclicCovariance.h"
#include "bcassim/distributed/MpiForecastProtocol.h"

namespace bcassim {

// The sigma-point set as it travels (SigmaPointColumns and the weights), and back.
Eigen::VectorXd packSigmaPoints(const SigmaPointColumns& columns, const Eigen::VectorXd& weights);
void unpackSigmaPoints(const Eigen::VectorXd& packed, SigmaPointColumns& columns,
                       Eigen::VectorXd& weights);

// Wall seconds of this rank's last step, for the cost model.
struct UkfShareTimes {
  double factor = 0, pdpotrf = 0, columns = 0, points = 0;
  double gramProducts = 0, gramReduce = 0, moments = 0, correct = 0;
};

class UkfCovarianceShare {
 public:
  // Collective (the process grid is made): `ranks` ranks, the set of every rank.
  UkfCovarianceShare(int ranks, SigmaPointColumns columns, Eigen::VectorXd weights);

  BlockCyclicCovariance& covariance() { return P_; }
  ColumnBlock block() const { return blocks_[static_cast<size_t>(rank_)]; }

  // This rank's sigma points x + spread C I^(k), k in block(), C the repaired factor of P
  // (x and spread the same on every rank). Throws NumericalError on every rank if P cannot be
  // factored.
  Eigen::MatrixXd drawPoints(const Eigen::VectorXd& x, double spread, RepairLog& repairs);
  // This rank's forecasts of those points (n x block().count), kept for moments() and correct().
  void keepForecasts(Eigen::MatrixXd forecasts) { forecasts_ = std::move(forecasts); }
  // The forecasts' weighted mean (on every rank) and P = their weighted Gram matrix about it,
  // divided by spread^2.
  Eigen::VectorXd moments(double spread);
  // With H (m x s, on rank 0; other ranks pass null) = C^-1 (w o dZ^T)^T: returns G = H D^T
  // (m x n, on every rank), D the deviations of moments(), and applies P -= G^T G.
  Eigen::MatrixXd correct(const Eigen::MatrixXd* H, int m);

  const UkfShareTimes& times() const { return times_; }

 private:
  int rank_ = 0;
  SigmaPointColumns columns_;
  Eigen::VectorXd weights_;
  std::vector<ColumnBlock> blocks_;
  std::vector<std::vector<Eigen::Index>> needed_;  // per rank: the factor's columns it reads
  std::vector<Eigen::Index> after_;                // per rank: the first column past its block
  BlockCyclicCovariance P_;
  Eigen::MatrixXd forecasts_, deviations_;
  UkfShareTimes times_;
};

}  // namespace bcassim
