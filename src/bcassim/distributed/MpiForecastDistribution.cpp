#include "bcassim/distributed/MpiForecastDistribution.h"

#include <fmt/format.h>
#include <mpi.h>

#include <optional>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/distributed/JobEndNotice.h"
#include "bcassim/distributed/MpiForecastProtocol.h"
#include "bcassim/distributed/MpiUkfCovariance.h"

namespace bcassim {

namespace proto = mpi_protocol;

namespace {

void sendHeader(const proto::Header& h, int rank) {
  checkMpi(MPI_Send(h.data(), 4, MPI_INT32_T, rank, proto::kCommandTag, MPI_COMM_WORLD),
           fmt::format("sending a command to rank {}", rank));
}

// A worker's error, rethrown on rank 0 as the type it had there.
[[noreturn]] void rethrow(std::int32_t kind, const std::string& message) {
  switch (kind) {
    case proto::kInputError:
      throw InputError(message);
    case proto::kOutputError:
      throw OutputError(message);
    case proto::kNumericalError:
      throw NumericalError(message);
    default:
      throw std::runtime_error(message);
  }
}

// Receives and drops the next payload from `rank` (an answer that cannot be used).
void dropPayload(int rank) {
  MPI_Status status;
  int bytes = 0;
  if (MPI_Probe(rank, proto::kAnswerPayloadTag, MPI_COMM_WORLD, &status) != MPI_SUCCESS) return;
  MPI_Get_count(&status, MPI_BYTE, &bytes);
  std::vector<char> dropped(static_cast<size_t>(bytes));
  MPI_Recv(dropped.data(), bytes, MPI_BYTE, rank, proto::kAnswerPayloadTag, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
}

}  // namespace

MpiForecastDistribution::MpiForecastDistribution(
    const MpiSession& session, std::function<std::string(int, const std::string&)> describeEnd)
    : size_(session.size()),
      describeEnd_(std::move(describeEnd)),
      sent_(static_cast<size_t>(session.size())),
      pending_(static_cast<size_t>(session.size()), false) {
  updateEndNotice();
}

MpiForecastDistribution::~MpiForecastDistribution() {
  drain();
  const proto::Header stop{proto::kStop, step_, 0, 0};
  for (int r = 1; r < size_; ++r)
    MPI_Send(stop.data(), 4, MPI_INT32_T, r, proto::kCommandTag, MPI_COMM_WORLD);
}

std::vector<MpiForecastDistribution::Block> MpiForecastDistribution::blocks(int columns) const {
  return equalColumnBlocks(columns, size_);
}

int MpiForecastDistribution::localColumns(int columns) const { return blocks(columns)[0].count; }

void MpiForecastDistribution::beginStep(int step) {
  step_ = step;
  updateEndNotice();
}

// The line for a job ended now, with the ranks that owe answers (none between forecasts).
void MpiForecastDistribution::updateEndNotice() {
  if (!describeEnd_) return;
  std::string ranks;
  for (int r = 1; r < size_; ++r)
    if (pending_[static_cast<size_t>(r)]) ranks += (ranks.empty() ? "" : ", ") + std::to_string(r);
  setJobEndNotice(describeEnd_(step_, ranks));
}

void MpiForecastDistribution::send(const Eigen::MatrixXd& points) {
  const Clock::time_point start = Clock::now();
  sent_ = blocks(static_cast<int>(points.cols()));
  ++stats_.steps;
  for (int r = 1; r < size_; ++r) {
    const Block& b = sent_[static_cast<size_t>(r)];
    if (b.count == 0) continue;
    sendHeader({proto::kForecast, step_, static_cast<std::int32_t>(points.rows()), b.count}, r);
    // A block of whole columns is contiguous in the column-major matrix: sent in place.
    const Eigen::Index n = points.rows() * b.count;
    checkMpi(MPI_Send(points.col(b.first).data(), static_cast<int>(n), MPI_DOUBLE, r,
                      proto::kCommandPayloadTag, MPI_COMM_WORLD),
             fmt::format("sending sigma points to rank {}", r));
    pending_[static_cast<size_t>(r)] = true;
    stats_.sentBytes += 8.0 * static_cast<double>(n);
  }
  updateEndNotice();
  stats_.sendSeconds += secondsSince(start);
}

void MpiForecastDistribution::receive(Eigen::MatrixXd& forecasts, Eigen::MatrixXd& observables) {
  const Clock::time_point start = Clock::now();
  std::optional<std::pair<std::int32_t, std::string>> failure;  // the first worker's error
  for (;;) {
    int owed = 0;
    for (int r = 1; r < size_; ++r) owed += pending_[static_cast<size_t>(r)] ? 1 : 0;
    if (owed == 0) break;
    proto::Header h{};
    const int r = waitForMessage(-1, proto::kAnswerTag, "waiting for a forecast's answer");
    checkMpi(
        MPI_Recv(h.data(), 4, MPI_INT32_T, r, proto::kAnswerTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
        "receiving a forecast's answer");
    const Block& b = sent_[static_cast<size_t>(r)];
    if (h[0] == proto::kOk &&
        (h[1] != forecasts.rows() || h[2] != observables.rows() || h[3] != b.count)) {
      dropPayload(r);
      dropPayload(r);
      if (!failure)
        failure.emplace(proto::kOtherError,
                        fmt::format("MPI rank {} answered {} x {} forecasts, expected {} x {}", r,
                                    h[1], h[3], forecasts.rows(), b.count));
    } else if (h[0] == proto::kOk) {
      const int n = h[1] * h[3], m = h[2] * h[3];
      checkMpi(MPI_Recv(forecasts.col(b.first).data(), n, MPI_DOUBLE, r, proto::kAnswerPayloadTag,
                        MPI_COMM_WORLD, MPI_STATUS_IGNORE),
               fmt::format("receiving forecasts from rank {}", r));
      checkMpi(MPI_Recv(observables.col(b.first).data(), m, MPI_DOUBLE, r, proto::kAnswerPayloadTag,
                        MPI_COMM_WORLD, MPI_STATUS_IGNORE),
               fmt::format("receiving observables from rank {}", r));
      stats_.receivedBytes += 8.0 * (n + m);
    } else {
      std::string text(static_cast<size_t>(h[1]), '\0');
      checkMpi(MPI_Recv(text.data(), h[1], MPI_CHAR, r, proto::kAnswerPayloadTag, MPI_COMM_WORLD,
                        MPI_STATUS_IGNORE),
               fmt::format("receiving rank {}'s error", r));
      if (!failure) failure.emplace(h[0], fmt::format("MPI rank {}: {}", r, text));
    }
    pending_[static_cast<size_t>(r)] = false;
    updateEndNotice();
  }
  stats_.receiveSeconds += secondsSince(start);
  if (failure) rethrow(failure->first, failure->second);
}

void MpiForecastDistribution::endStep(const Eigen::VectorXd& mean) {
  const Clock::time_point start = Clock::now();
  for (int r = 1; r < size_; ++r) {
    sendHeader({proto::kEndStep, step_, static_cast<std::int32_t>(mean.size()), 1}, r);
    checkMpi(MPI_Send(mean.data(), static_cast<int>(mean.size()), MPI_DOUBLE, r,
                      proto::kCommandPayloadTag, MPI_COMM_WORLD),
             fmt::format("sending the analysed mean to rank {}", r));
    stats_.sentBytes += 8.0 * static_cast<double>(mean.size());
  }
  stats_.endStepSeconds += secondsSince(start);
}

std::unique_ptr<UkfCovariance> MpiForecastDistribution::ukfCovariance(const SigmaPointSet& sigma) {
  if (size_ < 2 || sigma.structure == UnitStructure::Dense) return nullptr;
  return std::make_unique<MpiUkfCovariance>(*this, sigma);
}

void MpiForecastDistribution::tellWorkers(std::int32_t command, int rows, int columns,
                                          const Eigen::VectorXd& payload) {
  for (int r = 1; r < size_; ++r) {
    sendHeader({command, step_, rows, columns}, r);
    if (payload.size() > 0)
      checkMpi(MPI_Send(payload.data(), static_cast<int>(payload.size()), MPI_DOUBLE, r,
                        proto::kCommandPayloadTag, MPI_COMM_WORLD),
               fmt::format("sending a command's data to rank {}", r));
  }
}

void MpiForecastDistribution::expectAnswers(int columns) {
  sent_ = blocks(columns);
  ++stats_.steps;
  for (int r = 1; r < size_; ++r) pending_[static_cast<size_t>(r)] = true;
  updateEndNotice();
}

// Answers owed after an exception between send() and receive(): read and dropped, so that no
// worker stays blocked sending them.
void MpiForecastDistribution::drain() noexcept {
  for (int r = 1; r < size_; ++r) {
    if (!pending_[static_cast<size_t>(r)]) continue;
    proto::Header h{};
    if (MPI_Recv(h.data(), 4, MPI_INT32_T, r, proto::kAnswerTag, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE) != MPI_SUCCESS)
      continue;
    const int payloads = h[0] == proto::kOk ? 2 : 1;
    for (int p = 0; p < payloads; ++p) dropPayload(r);
    pending_[static_cast<size_t>(r)] = false;
  }
}

}  // namespace bcassim
