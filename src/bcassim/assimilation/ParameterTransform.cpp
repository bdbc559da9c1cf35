#include "bcassim/assimilation/ParameterTransform.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"

namespace bcassim {

TransformKind parseTransformKind(std::string_view name) {
  if (name == "none" || name == "identity") return TransformKind::Identity;
  if (name == "abs" || name == "absolute") return TransformKind::Absolute;
  if (name == "exp" || name == "log" || name == "exponential") return TransformKind::Exponential;
  if (name == "projection") return TransformKind::Projection;
  throw InputError(
      fmt::format("unknown parameter transform '{}': expected none, abs, exp or projection", name));
}

ParameterTransform ParameterTransform::projection(double lo, double hi) {
  if (!(lo < hi))
    throw InputError(fmt::format("projection bounds must satisfy min < max, got [{}, {}]", lo, hi));
  ParameterTransform t(TransformKind::Projection);
  t.lo_ = lo;
  t.hi_ = hi;
  return t;
}

double ParameterTransform::toPhysical(double u) const {
  switch (kind_) {
    case TransformKind::Identity:
      return u;
    case TransformKind::Absolute:
      return std::abs(u);
    case TransformKind::Exponential:
      return std::exp(u);
    case TransformKind::Projection:
      return std::clamp(u, lo_, hi_);
  }
  return u;
}

double ParameterTransform::toUnconstrained(double value) const {
  switch (kind_) {
    case TransformKind::Identity:
      return value;
    case TransformKind::Absolute:
      if (value < 0)
        throw InputError(
            fmt::format("value {} is negative; an absolute-value parameter is >= 0", value));
      return value;
    case TransformKind::Exponential:
      if (!(value > 0))
        throw InputError(
            fmt::format("value {} is not positive; an exponential parameter is > 0", value));
      return std::log(value);
    case TransformKind::Projection:
      if (value < lo_ || value > hi_)
        throw InputError(fmt::format("value {} lies outside [{}, {}]", value, lo_, hi_));
      return value;
  }
  return value;
}

double ParameterTransform::slope(double u) const {
  switch (kind_) {
    case TransformKind::Identity:
      return 1.0;
    case TransformKind::Absolute:
      return u < 0 ? -1.0 : 1.0;
    case TransformKind::Exponential:
      return std::exp(u);
    case TransformKind::Projection:
      return (u < lo_ || u > hi_) ? 0.0 : 1.0;
  }
  return 1.0;
}

double ParameterTransform::stddevToPhysical(double u, double sdU) const {
  return std::abs(slope(u)) * sdU;
}

double ParameterTransform::stddevToUnconstrained(double value, double sd) const {
  return sd / std::abs(slope(toUnconstrained(value)));
}

}  // namespace bcassim
