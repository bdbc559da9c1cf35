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
  if (name == "bounded-log") return TransformKind::BoundedLog;
  throw InputError(fmt::format(
      "unknown parameter transform '{}': expected none, abs, exp, projection or bounded-log",
      name));
}

ParameterTransform ParameterTransform::projection(double lo, double hi) {
  if (!(lo < hi))
    throw InputError(fmt::format("projection bounds must satisfy min < max, got [{}, {}]", lo, hi));
  ParameterTransform t(TransformKind::Projection);
  t.lo_ = lo;
  t.hi_ = hi;
  return t;
}

ParameterTransform ParameterTransform::boundedLog(double lo, double hi) {
  if (!(lo > 0 && lo < hi && std::isfinite(hi)))
    throw InputError(
        fmt::format("bounded-log bounds must satisfy 0 < min < max < inf, got [{}, {}]", lo, hi));
  ParameterTransform t(TransformKind::BoundedLog);
  t.lo_ = lo;
  t.hi_ = hi;
  return t;
}

namespace {

double logistic(double u) { return 1.0 / (1.0 + std::exp(-u)); }

// sigma(u) (1 - sigma(u)) written with exp(-|u|) so that it neither overflows nor cancels.
double logisticSlope(double u) {
  const double e = std::exp(-std::abs(u));
  return e / ((1.0 + e) * (1.0 + e));
}

}  // namespace

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
    case TransformKind::BoundedLog: {
      const double a = std::log(lo_), b = std::log(hi_);
      // exp rounds at the ends; the clamp keeps the promise lo <= physical <= hi exactly.
      return std::clamp(std::exp(a + (b - a) * logistic(u)), lo_, hi_);
    }
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
    case TransformKind::BoundedLog: {
      if (!(value > lo_ && value < hi_))
        throw InputError(fmt::format(
            "value {} lies outside ({}, {}); a bounded-log parameter is strictly inside its bounds",
            value, lo_, hi_));
      const double a = std::log(lo_), b = std::log(hi_);
      const double s = (std::log(value) - a) / (b - a);  // in (0, 1)
      return std::log(s) - std::log1p(-s);
    }
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
    case TransformKind::BoundedLog:
      return toPhysical(u) * std::log(hi_ / lo_) * logisticSlope(u);
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
