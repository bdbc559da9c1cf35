// The error an integrator throws when a step failed even at the smallest step it may cut to
// (time.min_dt): when (t, s) and why (the last failure: an inverted element, a linear or Newton
// solve that did not converge), so that a runner can add which step of its own it was.
#pragma once
#include <fmt/format.h>

#include <string>

#include "bcassim/Error.h"

namespace bcassim {

class StepFailure : public NumericalError {
 public:
  // integrator: "implicit Euler" or "static solver"; time: where the failed attempt started (s);
  // detail: what failed and how far the step was cut.
  StepFailure(const std::string& integrator, double time, std::string detail)
      : NumericalError(fmt::format("{} at t = {:.6g} s: {}", integrator, time, detail)),
        time_(time),
        detail_(std::move(detail)) {}

  double time() const { return time_; }
  const std::string& detail() const { return detail_; }

 private:
  double time_;
  std::string detail_;
};

}  // namespace bcassim
