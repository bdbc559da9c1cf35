// Scalar functions of time that modulate loads and prescribed displacements: constant, sine,
// square (+1/-1 alternating), pulse (1 then 0), half sine (a push one way only, as on a liver lobe
// held up by the diaphragm) and ramp, with a period and a phase in seconds.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

namespace bcassim {

struct TimeProfile {
  enum class Kind { Constant, Sine, Square, Pulse, Ramp, HalfSine };
  Kind kind = Kind::Constant;
  double period = 1.0;  // s (Ramp: time to reach 1)
  double phase = 0.0;   // s, shifts the profile: value(t) = shape(t + phase)

  double value(double t) const {
    const double s = t + phase;
    switch (kind) {
      case Kind::Constant:
        return 1.0;
      case Kind::Sine:
        return std::sin(2.0 * std::numbers::pi * s / period);
      case Kind::Square:
        return fraction(s) < 0.5 ? 1.0 : -1.0;
      case Kind::Pulse:
        return fraction(s) < 0.5 ? 1.0 : 0.0;
      case Kind::HalfSine:
        return std::max(0.0, std::sin(2.0 * std::numbers::pi * s / period));
      case Kind::Ramp:
        return s <= 0 ? 0.0 : (s >= period ? 1.0 : s / period);
    }
    return 1.0;
  }

 private:
  // Position within the current period in [0, 1); a small tolerance keeps t = k*period/2 (k
  // integer, as reached by summing time steps) on the side it is meant to be.
  double fraction(double s) const {
    const double f = s / period - std::floor(s / period + 1e-9);
    return f < 0 ? 0.0 : f;
  }
};

}  // namespace bcassim
