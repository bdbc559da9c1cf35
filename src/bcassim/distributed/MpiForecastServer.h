// A worker rank's side of the MPI executor (rank > 0): forecasts the block of sigma points /
// members rank 0 sends, with the rank's own models and threads, until rank 0 says stop.
#pragma once
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "bcassim/assimilation/ForecastEnsemble.h"
#include "bcassim/distributed/MpiSession.h"
#include "bcassim/distributed/UkfCovarianceShare.h"

namespace bcassim {

class MpiForecastServer {
 public:
  // Test-only fault injection, read here and nowhere else: BCASSIM_TEST_MPI_KILL=RANK:STEP makes
  // rank RANK kill itself (SIGKILL) on receiving the forecasts of step STEP, as a crashed node
  // would (tests/distributed/mpi_assimilate.sh).
  explicit MpiForecastServer(const MpiSession& session);

  // Answers rank 0's commands with `ensemble` (built from the same scene as rank 0's filter)
  // until it says stop. An error of a forecast or an endStep is answered in place of the next
  // forecasts; rank 0 rethrows it. Throws std::runtime_error only if MPI itself fails.
  void serve(ForecastEnsemble& ensemble);
  // The rank could not build its models (`error`, e.g. a scene it cannot read): answers that
  // error to every forecast until rank 0 says stop.
  void fail(const std::exception_ptr& error);

 private:
  void serveUntilStop(ForecastEnsemble* ensemble);
  // The collectives of a UKF covariance kept over the ranks (kUkfSetUp ... kUkfCorrect).
  void serveCovariance(const mpi_protocol::Header& h, ForecastEnsemble* ensemble);
  void answerError() const;
  void forgetStepFailure(const ForecastEnsemble* ensemble);
  void answerForecasts(const Eigen::MatrixXd& forecasts, const Eigen::MatrixXd& observables) const;

  int rank_, ranks_;
  int killAtStep_ = -1;  // BCASSIM_TEST_MPI_KILL
  // Answered to every forecast; a numerical one only to the step's (forgetStepFailure).
  std::optional<std::pair<std::int32_t, std::string>> failure_;
  std::unique_ptr<UkfCovarianceShare> share_;
};

}  // namespace bcassim
