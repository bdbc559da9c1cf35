#include "bcassim/calibration/UniaxialFit.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <unsupported/Eigen/NonLinearOptimization>

#include "bcassim/Error.h"

namespace bcassim {

namespace {

// p = lo + (hi - lo) logistic(u) with two finite bounds, lo + e^u or hi - e^u with one, u with
// none: the least-squares problem is unconstrained in u, the law never sees a value out of bounds.
struct BoundTransform {
  ParameterBound b;
  bool lo() const { return std::isfinite(b.lower); }
  bool hi() const { return std::isfinite(b.upper); }
  double physical(double u) const {
    if (lo() && hi()) return b.lower + (b.upper - b.lower) / (1.0 + std::exp(-u));
    if (lo()) return b.lower + std::exp(u);
    if (hi()) return b.upper - std::exp(u);
    return u;
  }
  double slope(double u) const {
    if (lo() && hi()) {
      const double s = 1.0 / (1.0 + std::exp(-u));
      return (b.upper - b.lower) * s * (1.0 - s);
    }
    if (lo()) return std::exp(u);
    if (hi()) return -std::exp(u);
    return 1.0;
  }
  // The start moved strictly inside the bounds (1e-3 of the range, or of the value's size).
  double unconstrained(double p) const {
    const double margin = 1e-3 * ((lo() && hi()) ? b.upper - b.lower : std::max(1.0, std::abs(p)));
    if (lo()) p = std::max(p, b.lower + margin);
    if (hi()) p = std::min(p, b.upper - margin);
    if (lo() && hi()) {
      const double s = (p - b.lower) / (b.upper - b.lower);
      return std::log(s / (1.0 - s));
    }
    if (lo()) return std::log(p - b.lower);
    if (hi()) return std::log(b.upper - p);
    return p;
  }
};

struct Residuals {
  using Scalar = double;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;

  const UniaxialCurve& curve;
  UniaxialLaw law;
  std::vector<BoundTransform> transforms;

  int inputs() const { return static_cast<int>(transforms.size()); }
  int values() const { return static_cast<int>(curve.stretch.size()); }
  Eigen::VectorXd physical(const Eigen::VectorXd& u) const {
    Eigen::VectorXd p(u.size());
    for (Eigen::Index k = 0; k < u.size(); ++k) p(k) = transforms[k].physical(u(k));
    return p;
  }
  int operator()(const Eigen::VectorXd& u, Eigen::VectorXd& r) const {
    const Eigen::VectorXd p = physical(u);
    for (Eigen::Index i = 0; i < curve.stretch.size(); ++i)
      r(i) = uniaxialNominalStress(law, p, curve.stretch(i)) - curve.nominalStress(i);
    return r.allFinite() ? 0 : -1;  // a negative value stops the minimisation
  }
  int df(const Eigen::VectorXd& u, Eigen::MatrixXd& J) const {
    const Eigen::VectorXd p = physical(u);
    for (Eigen::Index i = 0; i < curve.stretch.size(); ++i)
      J.row(i) = uniaxialNominalStressGradient(law, p, curve.stretch(i)).transpose();
    for (Eigen::Index k = 0; k < u.size(); ++k) J.col(k) *= transforms[k].slope(u(k));
    return 0;
  }
};

// Least squares over the parameters the stress is linear in (all of them but Ogden's alpha).
Eigen::VectorXd linearStart(const UniaxialCurve& c, UniaxialLaw law, double alpha) {
  const Eigen::Index n = c.stretch.size();
  // One entry per parameter (a ternary would convert every branch to the fixed-size Vector2d).
  Eigen::VectorXd p =
      Eigen::VectorXd::Ones(static_cast<Eigen::Index>(uniaxialParameterNames(law).size()));
  if (law == UniaxialLaw::Ogden) p(1) = alpha;
  const int linear = law == UniaxialLaw::MooneyRivlin ? 2 : 1;
  Eigen::MatrixXd G(n, linear);
  for (Eigen::Index i = 0; i < n; ++i)
    G.row(i) = uniaxialNominalStressGradient(law, p, c.stretch(i)).head(linear).transpose();
  p.head(linear) = G.colPivHouseholderQr().solve(c.nominalStress);
  return p;
}

Eigen::VectorXd startingPoint(const UniaxialCurve& c, UniaxialLaw law) {
  if (law != UniaxialLaw::Ogden) return linearStart(c, law, 0.0);
  // Ogden: the best alpha of a grid, each with its own least-squares mu.
  Eigen::VectorXd best;
  double bestSsr = std::numeric_limits<double>::infinity();
  for (double alpha = -30.0; alpha <= 30.0; alpha += 0.5) {
    if (alpha == 0.0) continue;
    const Eigen::VectorXd p = linearStart(c, law, alpha);
    double ssr = 0.0;
    for (Eigen::Index i = 0; i < c.stretch.size(); ++i)
      ssr += std::pow(uniaxialNominalStress(law, p, c.stretch(i)) - c.nominalStress(i), 2);
    if (std::isfinite(ssr) && ssr < bestSsr) bestSsr = ssr, best = p;
  }
  return best.size() ? best : Eigen::VectorXd(Eigen::Vector2d(1.0, 2.0));
}

}  // namespace

UniaxialFitResult fitUniaxial(const UniaxialCurve& curve, UniaxialLaw law,
                              const UniaxialFitOptions& options) {
  UniaxialFitResult out;
  out.law = law;
  out.names = uniaxialParameterNames(law);
  out.units = uniaxialParameterUnits(law);
  const Eigen::Index p = static_cast<Eigen::Index>(out.names.size());
  std::vector<BoundTransform> transforms(p);
  if (law != UniaxialLaw::MooneyRivlin) transforms[0].b.lower = 0.0;  // mu > 0
  for (const auto& [name, bound] : options.bounds) {
    const auto it = std::find(out.names.begin(), out.names.end(), name);
    if (it == out.names.end())
      throw InputError(fmt::format("bound on '{}': the {} law has parameters {}", name,
                                   uniaxialLawName(law), fmt::join(out.names, ", ")));
    if (!(bound.lower < bound.upper))
      throw InputError(fmt::format("bound on '{}': lower {:g} must be below upper {:g}", name,
                                   bound.lower, bound.upper));
    transforms[it - out.names.begin()].b = bound;
  }
  if (curve.stretch.size() < p)
    throw InputError(fmt::format("{} points for the {} parameters of {}: expected at least {}",
                                 curve.stretch.size(), p, uniaxialLawName(law), p));

  Residuals f{curve, law, transforms};
  const Eigen::VectorXd start = startingPoint(curve, law);
  Eigen::VectorXd u(p);
  for (Eigen::Index k = 0; k < p; ++k) u(k) = transforms[k].unconstrained(start(k));
  Eigen::LevenbergMarquardt<Residuals> lm(f);
  lm.parameters.ftol = 1e-15;
  lm.parameters.xtol = 1e-15;
  lm.parameters.gtol = 0.0;
  lm.parameters.maxfev = options.maxEvaluations;
  const auto status = lm.minimize(u);
  out.evaluations = static_cast<int>(lm.nfev);
  using namespace Eigen::LevenbergMarquardtSpace;
  // Statuses 1-4 converged; 6-8 say the tolerances cannot be met in floating point: the solution
  // is as good as it gets (an exact fit ends there). 0, 5 and user stops did not converge.
  if (status == ImproperInputParameters || status == TooManyFunctionEvaluation ||
      status == UserAsked || !u.allFinite())
    throw NumericalError(fmt::format(
        "fitting {}: Levenberg-Marquardt did not converge ({} after {} evaluations)",
        uniaxialLawName(law),
        status == TooManyFunctionEvaluation ? "evaluation budget spent" : "non-finite residual",
        out.evaluations));

  out.parameters = f.physical(u);
  out.residuals.resize(curve.stretch.size());
  f(u, out.residuals);
  const Eigen::Index n = curve.stretch.size();
  const double ssr = out.residuals.squaredNorm();
  out.rmsResidual = std::sqrt(ssr / static_cast<double>(n));
  const double sst = (curve.nominalStress.array() - curve.nominalStress.mean()).square().sum();
  out.rSquared = sst > 0 ? 1.0 - ssr / sst : 1.0;
  out.shearModulus = uniaxialShearModulus(law, out.parameters);

  Eigen::MatrixXd J(n, p);
  for (Eigen::Index i = 0; i < n; ++i)
    J.row(i) = uniaxialNominalStressGradient(law, out.parameters, curve.stretch(i)).transpose();
  out.standardErrors = Eigen::VectorXd::Constant(p, std::numeric_limits<double>::quiet_NaN());
  if (n > p) {
    const double s2 = ssr / static_cast<double>(n - p);
    const Eigen::MatrixXd cov = s2 * (J.transpose() * J).inverse();
    out.standardErrors = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  }
  return out;
}

}  // namespace bcassim
