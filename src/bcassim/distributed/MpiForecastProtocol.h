// What rank 0 and the worker ranks say to each other: a four-integer header, then its payload
// (doubles, column-major, or an error's text) as a second message with its own tag.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace bcassim::mpi_protocol {

// Rank 0 -> worker: {command, step, rows, columns}, then rows x columns doubles (none for Stop).
// A full-state UKF's covariance kept over the ranks (UkfCovarianceShare.h), every command a
// collective the worker joins: kUkfSetUp {n, payload size} with the packed sigma-point set;
// kCovAssign, kCovGather, kCovDiagonal, kCovKeep, kCovRestore without payload; kCovAddDiagonal
// with n doubles; kUkfForecast {n, s} with the mean and the spread (n + 1 doubles), answered as a
// forecast is, with no forecast rows (only observables); kUkfMoments with the spread;
// kUkfCorrect {m, s}, H's columns scattered in the collective.
enum Command : std::int32_t {
  kForecast = 1,
  kEndStep = 2,
  kStop = 3,
  kUkfSetUp = 4,
  kCovAssign = 5,
  kCovGather = 6,
  kCovDiagonal = 7,
  kCovAddDiagonal = 8,
  kCovKeep = 9,
  kCovRestore = 10,
  kUkfForecast = 11,
  kUkfMoments = 12,
  kUkfCorrect = 13,
};
// Worker -> rank 0: {kOk, rows, observable rows, columns}, then the forecasts and the observables
// as two payloads; or {error kind, text length, 0, 0}, then the text.
enum Answer : std::int32_t {
  kOk = 0,
  kInputError = 1,
  kOutputError = 2,
  kNumericalError = 3,
  kOtherError = 4
};
using Header = std::array<std::int32_t, 4>;

constexpr int kCommandTag = 17001, kCommandPayloadTag = 17002;
constexpr int kAnswerTag = 17003, kAnswerPayloadTag = 17004;

}  // namespace bcassim::mpi_protocol

namespace bcassim {

// A rank's columns of the step's sigma points / members.
struct ColumnBlock {
  int first = 0, count = 0;
};

// Equal blocks in rank order, the first ranks taking one more when the columns do not divide.
inline std::vector<ColumnBlock> equalColumnBlocks(int columns, int ranks) {
  std::vector<ColumnBlock> out(static_cast<size_t>(ranks));
  int first = 0;
  for (int r = 0; r < ranks; ++r) {
    const int count = columns / ranks + (r < columns % ranks ? 1 : 0);
    out[static_cast<size_t>(r)] = {first, count};
    first += count;
  }
  return out;
}

}  // namespace bcassim
