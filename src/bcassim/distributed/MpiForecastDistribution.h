// Rank 0's side of the MPI executor: each step's sigma points / members split into one block of
// columns per rank, rank 0 keeping the first; the others' forecasts gathered back (thesis §3.3's
// independent forecasts, ranks x threads).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bcassim/assimilation/ForecastDistribution.h"
#include "bcassim/distributed/MpiForecastProtocol.h"
#include "bcassim/distributed/MpiSession.h"

namespace bcassim {

// What one step moved between the ranks, for the benchmarks' cost model.
struct MpiTransferStats {
  int steps = 0;                            // forecasts sent (one per step)
  double sentBytes = 0, receivedBytes = 0;  // payloads of forecasts and endStep
  double sendSeconds = 0;                   // rank 0 in send(): columns out
  double receiveSeconds = 0;                // rank 0 in receive(): waiting and columns in
  double endStepSeconds = 0;                // rank 0 sending the analysed mean
  // A full-state UKF's covariance kept over the ranks (MpiUkfCovariance): steps after the first
  // (which faults its buffers in), and rank 0's wall time in each part of them (factor: pdpotrf and
  // its agreements; columns: the factor's columns handed out and the suffix sums; points: its own
  // sigma points; gram: the mean and the Gram matrix, of which its products and the reduce-scatter;
  // correct: the gain and P -= G^T G).
  int covarianceSteps = 0;
  double factorSeconds = 0, pdpotrfSeconds = 0, columnsSeconds = 0, pointsSeconds = 0;
  double gramSeconds = 0, gramProductSeconds = 0, gramReduceSeconds = 0, correctSeconds = 0;
};

class MpiForecastDistribution final : public ForecastDistribution {
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
  // With more than one rank: the covariance kept by every rank (MpiUkfCovariance.h).
  std::unique_ptr<UkfCovariance> ukfCovariance(const SigmaPointSet& sigma) override;

  // Totals since the start (payload bytes and rank 0's wall time in each call).
  const MpiTransferStats& stats() const { return stats_; }

 private:
  friend class MpiUkfCovariance;
  using Block = ColumnBlock;
  // {command, this step, rows, columns} and `payload` (none if empty) to every worker.
  void tellWorkers(std::int32_t command, int rows, int columns,
                   const Eigen::VectorXd& payload = Eigen::VectorXd());
  // Every worker owes a forecast's answer for its block of `columns` (receive() collects them).
  void expectAnswers(int columns);
  std::vector<Block> blocks(int columns) const;
  void updateEndNotice();
  void drain() noexcept;

  int size_;
  std::function<std::string(int, const std::string&)> describeEnd_;
  int step_ = 0;
  std::vector<Block> sent_;    // per rank: the columns it was given this step
  std::vector<bool> pending_;  // per rank: its answer is still owed
  MpiTransferStats stats_;
};

}  // namespace bcassim
