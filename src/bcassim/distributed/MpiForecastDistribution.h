// Rank 0's side of the MPI executor: each step's sigma points / members split into one block of
// columns per rank, rank 0 keeping the first; the others' forecasts gathered back (thesis §3.3's
// independent forecasts, ranks x threads).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bcassim/assimilation/DenseAlgebra.h"
#include "bcassim/assimilation/ForecastDistribution.h"
#include "bcassim/distributed/MpiSession.h"
#include "bcassim/distributed/ScalapackCholesky.h"
#include "bcassim/distributed/SharedGram.h"

namespace bcassim {

// What one step moved between the ranks, for the benchmarks' cost model.
struct MpiTransferStats {
  int steps = 0;                            // forecasts sent (one per step)
  double sentBytes = 0, receivedBytes = 0;  // payloads of forecasts and endStep
  double sendSeconds = 0;                   // rank 0 in send(): columns out
  double receiveSeconds = 0;                // rank 0 in receive(): waiting and columns in
  double endStepSeconds = 0;                // rank 0 sending the analysed mean
  // The filter's shared dense algebra (a full-state UKF): rank 0's wall time in the Gram
  // matrices (its own block, the reduction, the shifts to the mean) and the Cholesky factors (A
  // out to the grid, pdpotrf, L back), and the bytes rank 0 took part in moving for them.
  int grams = 0, factorizations = 0;
  double gramSeconds = 0, choleskySeconds = 0;
  double gramBytes = 0, choleskyBytes = 0;
};

class MpiForecastDistribution final : public ForecastDistribution, public DenseAlgebra {
 public:
  // On rank 0 of `session`, whose other ranks run MpiForecastServer::serve. `describeEnd(step,
  // ranks)` words the line printed if the job is ended during `step` while `ranks` (e.g. "2" or
  // "1, 2"; empty: none) owe forecasts (JobEndNotice.h).
  MpiForecastDistribution(
      const MpiSession& session,
      std::function<std::string(int step, const std::string& ranks)> describeEnd);
  // Collects any answers still owed (an exception left a step half done), then tells every
  // worker rank to stop. Never throws.
  ~MpiForecastDistribution() override;

  int localColumns(int columns) const override;
  void beginStep(int step) override;
  void send(const Eigen::MatrixXd& points) override;
  void receive(Eigen::MatrixXd& forecasts, Eigen::MatrixXd& observables) override;
  void endStep(const Eigen::VectorXd& mean) override;
  // With more than one rank: the Gram matrix reduced over the ranks' blocks (SharedGram.h) and
  // the Cholesky factor computed by all of them (ScalapackCholesky.h).
  DenseAlgebra* sharedAlgebra() override { return size_ > 1 ? this : nullptr; }
  void weightedGram(const Eigen::MatrixXd& deviations, const Eigen::VectorXd& w, double scale,
                    Eigen::MatrixXd& P) override;
  bool choleskyLower(const Eigen::MatrixXd& A, Eigen::MatrixXd& L) override;

  // Totals since the start (payload bytes and rank 0's wall time in each call).
  const MpiTransferStats& stats() const { return stats_; }

 private:
  using Block = ColumnBlock;
  std::vector<Block> blocks(int columns) const;
  void updateEndNotice();
  void drain() noexcept;

  int size_;
  std::function<std::string(int, const std::string&)> describeEnd_;
  int step_ = 0;
  std::vector<Block> sent_;    // per rank: the columns it was given this step
  std::vector<bool> pending_;  // per rank: its answer is still owed
  MpiTransferStats stats_;
  ScalapackCholesky cholesky_;
  Eigen::VectorXd packedGram_;  // the Gram matrix's lower triangle, reduced
};

}  // namespace bcassim
