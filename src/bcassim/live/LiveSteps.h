// The two callables the live engine drives, and a helper that makes the real-time one from a
// predictor and a sink. The engine knows neither models nor filters, only these.
#pragma once
#include <functional>
#include <utility>

#include "bcassim/live/Frame.h"
#include "bcassim/live/ParameterSet.h"

namespace bcassim {

// Advances the model by one frame with the given parameters and hands the result on (to the
// display). Runs on the real-time side: it must not wait for the filter.
using RealTimeStep = std::function<void(const Frame&, const ParameterSet&)>;

// Analyses one frame (the filter's forecast and correction) and returns the new parameters'
// mean and covariance; the engine sets their `frame`. The filter keeps its own state between
// calls; frames come in increasing order, possibly with gaps where frames were skipped.
using FilterStep = std::function<ParameterSet(const Frame&)>;

// A real-time step from a predictor (Frame, ParameterSet) -> R (e.g. hidden points with their
// 95 % radius) and a sink (Frame, R) that publishes it.
template <class Predictor, class Sink>
RealTimeStep predictThenPublish(Predictor predict, Sink sink) {
  return [predict = std::move(predict), sink = std::move(sink)](
             const Frame& frame, const ParameterSet& parameters) mutable {
    sink(frame, predict(frame, parameters));
  };
}

}  // namespace bcassim
