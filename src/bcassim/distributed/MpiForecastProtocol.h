// What rank 0 and the worker ranks say to each other: a four-integer header, then its payload
// (doubles, column-major, or an error's text) as a second message with its own tag.
#pragma once
#include <array>
#include <cstdint>

namespace bcassim::mpi_protocol {

// Rank 0 -> worker: {command, step, rows, columns}, then rows x columns doubles (none for Stop).
// Gram: {kGram, step, state rows, the worker's columns}, then the deviations' scale and the
// columns' weights (columns + 1 doubles); the worker adds its block's Gram matrix into rank 0's
// (SharedGram.h). Cholesky: {kCholesky, step, n, n}, no payload; every rank joins the
// factorisation (ScalapackCholesky.h).
enum Command : std::int32_t { kForecast = 1, kEndStep = 2, kStop = 3, kGram = 4, kCholesky = 5 };
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
