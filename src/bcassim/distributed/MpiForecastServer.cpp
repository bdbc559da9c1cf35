#include "bcassim/distributed/MpiForecastServer.h"

#include <fmt/format.h>
#include <mpi.h>

#include <csignal>
#include <cstdlib>
#include <limits>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/distributed/MpiForecastProtocol.h"

namespace bcassim {

namespace proto = mpi_protocol;

namespace {

// The answer kind and text of an exception, so that rank 0 rethrows the same kind of error.
std::pair<std::int32_t, std::string> describe(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const OutputError& e) {
    return {proto::kOutputError, e.what()};
  } catch (const InputError& e) {
    return {proto::kInputError, e.what()};
  } catch (const NumericalError& e) {
    return {proto::kNumericalError, e.what()};
  } catch (const std::exception& e) {
    return {proto::kOtherError, e.what()};
  } catch (...) {
    return {proto::kOtherError, "unknown exception"};
  }
}

// RANK:STEP of BCASSIM_TEST_MPI_KILL for this rank; -1 when unset or for another rank.
int killStepFor(int rank) {
  const char* value = std::getenv("BCASSIM_TEST_MPI_KILL");
  if (value == nullptr) return -1;
  int r = -1, step = -1;
  if (std::sscanf(value, "%d:%d", &r, &step) != 2 || r != rank) return -1;
  return step;
}

void sendAnswer(const proto::Header& h) {
  checkMpi(MPI_Send(h.data(), 4, MPI_INT32_T, 0, proto::kAnswerTag, MPI_COMM_WORLD),
           "answering rank 0");
}

// The next command's payload of `size` doubles.
Eigen::VectorXd receivePayload(Eigen::Index size, const char* what) {
  Eigen::VectorXd payload(size);
  checkMpi(MPI_Recv(payload.data(), static_cast<int>(size), MPI_DOUBLE, 0,
                    proto::kCommandPayloadTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
           what);
  return payload;
}

}  // namespace

MpiForecastServer::MpiForecastServer(const MpiSession& session)
    : rank_(session.rank()), ranks_(session.size()), killAtStep_(killStepFor(session.rank())) {}

void MpiForecastServer::serve(ForecastEnsemble& ensemble) { serveUntilStop(&ensemble); }

void MpiForecastServer::fail(const std::exception_ptr& error) {
  failure_ = describe(error);
  serveUntilStop(nullptr);
}

void MpiForecastServer::answerError() const {
  sendAnswer({failure_->first, static_cast<std::int32_t>(failure_->second.size()), 0, 0});
  checkMpi(MPI_Send(failure_->second.data(), static_cast<int>(failure_->second.size()), MPI_CHAR, 0,
                    proto::kAnswerPayloadTag, MPI_COMM_WORLD),
           "answering rank 0");
}

// A numerical failure belongs to one step's forecasts: rank 0 may redo the step with its sigma
// points closer to the mean (ForecastEnsemble::forecastRetrying), so this rank serves again. Any
// other failure (and any before the set-up ended) is answered to every later command.
void MpiForecastServer::forgetStepFailure(const ForecastEnsemble* ensemble) {
  if (ensemble && failure_ && failure_->first == proto::kNumericalError) failure_.reset();
}

void MpiForecastServer::answerForecasts(const Eigen::MatrixXd& forecasts,
                                        const Eigen::MatrixXd& observables) const {
  sendAnswer({proto::kOk, static_cast<std::int32_t>(forecasts.rows()),
              static_cast<std::int32_t>(observables.rows()),
              static_cast<std::int32_t>(observables.cols())});
  checkMpi(MPI_Send(forecasts.data(), static_cast<int>(forecasts.size()), MPI_DOUBLE, 0,
                    proto::kAnswerPayloadTag, MPI_COMM_WORLD),
           "sending forecasts to rank 0");
  checkMpi(MPI_Send(observables.data(), static_cast<int>(observables.size()), MPI_DOUBLE, 0,
                    proto::kAnswerPayloadTag, MPI_COMM_WORLD),
           "sending observables to rank 0");
}

// Joined whatever this rank's state (a failure is answered at the next forecasts), so that no
// collective hangs.
void MpiForecastServer::serveCovariance(const proto::Header& h, ForecastEnsemble* ensemble) {
  if (h[0] == proto::kUkfSetUp) {
    SigmaPointColumns columns;
    Eigen::VectorXd weights;
    unpackSigmaPoints(receivePayload(h[3], "receiving the sigma points"), columns, weights);
    share_ = std::make_unique<UkfCovarianceShare>(ranks_, std::move(columns), std::move(weights));
    return;
  }
  if (!share_) throw std::runtime_error("MPI: a covariance command before the UKF's set-up");
  BlockCyclicCovariance& P = share_->covariance();
  switch (h[0]) {
    case proto::kCovAssign:
      P.scatter(nullptr);
      return;
    case proto::kCovGather:
      P.gather(nullptr);
      return;
    case proto::kCovDiagonal:
      P.diagonal();
      return;
    case proto::kCovAddDiagonal:
      P.addToDiagonal(receivePayload(h[2], "receiving the process noise"));
      return;
    case proto::kCovKeep:
      P.keep();
      return;
    case proto::kCovRestore:
      P.restore();
      return;
    case proto::kUkfMoments:
      share_->moments(receivePayload(1, "receiving the sigma points' spread")(0));
      return;
    case proto::kUkfCorrect:
      share_->correct(nullptr, h[2]);
      return;
    default:
      break;
  }
  // kUkfForecast: this rank's sigma points, forecast, and their observables to rank 0.
  const Eigen::VectorXd payload = receivePayload(h[2] + 1, "receiving the mean to forecast from");
  if (h[1] == killAtStep_) std::raise(SIGKILL);
  Eigen::MatrixXd points;
  RepairLog ignored;  // rank 0 reports the repairs
  try {
    points = share_->drawPoints(payload.head(h[2]), payload(h[2]), ignored);
  } catch (...) {
    if (!failure_) failure_ = describe(std::current_exception());
  }
  Eigen::MatrixXd forecasts, observables;
  if (!failure_ && ensemble) {
    try {
      ensemble->forecast(points, forecasts, observables);
      share_->keepForecasts(std::move(forecasts));
    } catch (...) {
      failure_ = describe(std::current_exception());
    }
  }
  if (failure_) {
    answerError();
    forgetStepFailure(ensemble);
    return;
  }
  answerForecasts(Eigen::MatrixXd(0, observables.cols()), observables);
}

void MpiForecastServer::serveUntilStop(ForecastEnsemble* ensemble) {
  Eigen::MatrixXd points, forecasts, observables;
  Eigen::VectorXd mean;
  for (;;) {
    proto::Header h{};
    waitForMessage(0, proto::kCommandTag, "waiting for a command from rank 0");
    checkMpi(MPI_Recv(h.data(), 4, MPI_INT32_T, 0, proto::kCommandTag, MPI_COMM_WORLD,
                      MPI_STATUS_IGNORE),
             "receiving a command from rank 0");
    if (h[0] == proto::kStop) return;
    if (h[0] == proto::kEndStep) {
      mean.resize(h[2]);
      checkMpi(MPI_Recv(mean.data(), h[2], MPI_DOUBLE, 0, proto::kCommandPayloadTag, MPI_COMM_WORLD,
                        MPI_STATUS_IGNORE),
               "receiving the analysed mean");
      if (failure_ || !ensemble) continue;
      try {
        ensemble->endStep(mean);
      } catch (...) {
        failure_ = describe(std::current_exception());
      }
      continue;
    }
    if (h[0] != proto::kForecast) {
      serveCovariance(h, ensemble);
      continue;
    }
    points.resize(h[2], h[3]);
    checkMpi(MPI_Recv(points.data(), h[2] * h[3], MPI_DOUBLE, 0, proto::kCommandPayloadTag,
                      MPI_COMM_WORLD, MPI_STATUS_IGNORE),
             "receiving sigma points");
    if (h[1] == killAtStep_) std::raise(SIGKILL);
    if (!failure_ && ensemble) {
      try {
        ensemble->forecast(points, forecasts, observables);
      } catch (...) {
        failure_ = describe(std::current_exception());
      }
    }
    if (failure_) {
      answerError();
      forgetStepFailure(ensemble);
      continue;
    }
    answerForecasts(forecasts, observables);
  }
}

}  // namespace bcassim
