#include "bcassim/distributed/MpiForecastServer.h"

#include <fmt/format.h>
#include <mpi.h>

#include <csignal>
#include <cstdlib>
#include <limits>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/distributed/MpiForecastProtocol.h"
#include "bcassim/distributed/SharedGram.h"

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

}  // namespace

MpiForecastServer::MpiForecastServer(const MpiSession& session)
    : rank_(session.rank()), killAtStep_(killStepFor(session.rank())), cholesky_(session.size()) {}

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

void MpiForecastServer::serveUntilStop(ForecastEnsemble* ensemble) {
  Eigen::MatrixXd points, forecasts, observables;
  SharedGramWorkspace gram;
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
    // The shared algebra: joined whatever this rank's state, so that no collective hangs.
    if (h[0] == proto::kCholesky) {
      cholesky_.factor(h[2], nullptr, nullptr);
      continue;
    }
    if (h[0] == proto::kGram) {
      Eigen::VectorXd payload(h[3] + 1);
      checkMpi(MPI_Recv(payload.data(), h[3] + 1, MPI_DOUBLE, 0, proto::kCommandPayloadTag,
                        MPI_COMM_WORLD, MPI_STATUS_IGNORE),
               "receiving the weights of the Gram matrix");
      // Rank 0 asks only after every forecast came back; a block this rank does not hold (a
      // protocol error) adds NaN, so that rank 0 stops on a non-finite covariance instead of
      // using one without these columns.
      const bool have = !failure_ && forecasts.rows() == h[2] && forecasts.cols() == h[3];
      const Eigen::MatrixXd missing =
          have ? Eigen::MatrixXd()
               : Eigen::MatrixXd::Constant(h[2], h[3], std::numeric_limits<double>::quiet_NaN());
      contributeBlockGram(have ? forecasts : missing, payload.tail(h[3]), payload[0], h[2], gram);
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
      continue;
    }
    sendAnswer({proto::kOk, static_cast<std::int32_t>(forecasts.rows()),
                static_cast<std::int32_t>(observables.rows()),
                static_cast<std::int32_t>(forecasts.cols())});
    checkMpi(MPI_Send(forecasts.data(), static_cast<int>(forecasts.size()), MPI_DOUBLE, 0,
                      proto::kAnswerPayloadTag, MPI_COMM_WORLD),
             "sending forecasts to rank 0");
    checkMpi(MPI_Send(observables.data(), static_cast<int>(observables.size()), MPI_DOUBLE, 0,
                      proto::kAnswerPayloadTag, MPI_COMM_WORLD),
             "sending observables to rank 0");
  }
}

}  // namespace bcassim
