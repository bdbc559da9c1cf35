// Map between a parameter's physical value and the unconstrained value a Kalman filter estimates.
// A positive stiffness is estimated in log space so that Gaussian sigma points never go negative.
#pragma once
#include <string_view>

namespace bcassim {

enum class TransformKind {
  Identity,     // physical = u
  Absolute,     // physical = |u|: a sign flip of the estimate is read as the same stiffness
  Exponential,  // physical = exp(u): the filter estimates log(value)
  Projection,   // physical = clamp(u, lo, hi): the estimate may leave the box, the model never does
  // physical = exp(a + (b - a) sigma(u)), lo = e^a < hi = e^b, sigma the logistic: log space
  // squeezed smoothly into (lo, hi), so sigma points never leave the box and the slope never
  // vanishes inside it (unlike Projection, whose clamped sigma points carry no information).
  BoundedLog,
};

// Parses "none", "abs", "exp" (alias "log"), "projection" or "bounded-log"; throws InputError
// otherwise.
TransformKind parseTransformKind(std::string_view name);

// One scalar transform u -> physical value. Standard deviations are pushed through the slope at
// the mean (first-order, delta method), so sd_phys = |d phys/du| * sd_u in both directions.
class ParameterTransform {
 public:
  ParameterTransform() = default;  // identity
  static ParameterTransform identity() { return {}; }
  static ParameterTransform absolute() { return ParameterTransform(TransformKind::Absolute); }
  static ParameterTransform exponential() { return ParameterTransform(TransformKind::Exponential); }
  // Throws InputError unless lo < hi.
  static ParameterTransform projection(double lo, double hi);
  // Throws InputError unless 0 < lo < hi (both finite).
  static ParameterTransform boundedLog(double lo, double hi);

  TransformKind kind() const { return kind_; }
  double lower() const { return lo_; }
  double upper() const { return hi_; }

  double toPhysical(double u) const;
  // Inverse on the physical range of the transform; throws InputError for a value outside it
  // (non-positive for Exponential, negative for Absolute, outside [lo, hi] for Projection,
  // outside the open (lo, hi) for BoundedLog).
  double toUnconstrained(double value) const;
  // d physical / d u at u: 1, sign(u) (1 at 0), exp(u), 1 inside the box and 0 outside, or
  // physical (b - a) sigma(u) (1 - sigma(u)) for BoundedLog.
  double slope(double u) const;

  double stddevToPhysical(double u, double sdU) const;
  // Inverse of stddevToPhysical at the physical value `value` (where the slope is never zero).
  double stddevToUnconstrained(double value, double sd) const;

 private:
  explicit ParameterTransform(TransformKind kind) : kind_(kind) {}
  TransformKind kind_ = TransformKind::Identity;
  double lo_ = 0.0;
  double hi_ = 0.0;
};

}  // namespace bcassim
