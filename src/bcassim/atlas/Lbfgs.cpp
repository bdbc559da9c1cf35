#include "bcassim/atlas/Lbfgs.h"

#include <fmt/format.h>

#include <cmath>
#include <deque>
#include <limits>

#include "bcassim/Error.h"

namespace bcassim {
namespace {
struct Pair {
  Eigen::VectorXd s, y;
  double rho;
};

// Two-loop recursion: -H g with the scaled identity as initial inverse Hessian.
Eigen::VectorXd direction(const std::deque<Pair>& mem, const Eigen::VectorXd& g) {
  Eigen::VectorXd q = g;
  std::vector<double> alpha(mem.size());
  for (size_t k = mem.size(); k-- > 0;) {
    alpha[k] = mem[k].rho * mem[k].s.dot(q);
    q -= alpha[k] * mem[k].y;
  }
  if (!mem.empty()) q *= mem.back().s.dot(mem.back().y) / mem.back().y.squaredNorm();
  for (size_t k = 0; k < mem.size(); ++k) {
    const double beta = mem[k].rho * mem[k].y.dot(q);
    q += (alpha[k] - beta) * mem[k].s;
  }
  return -q;
}
}  // namespace

LbfgsResult minimizeLbfgs(const LbfgsObjective& f, Eigen::VectorXd x0,
                          const LbfgsOptions& options) {
  if (options.memory < 1 || options.maxIterations < 0 ||
      !(options.armijo > 0.0 && options.armijo < options.wolfe && options.wolfe < 1.0)) {
    throw InputError(fmt::format("L-BFGS: bad options (memory {}, c1 {}, c2 {})", options.memory,
                                 options.armijo, options.wolfe));
  }
  LbfgsResult r;
  r.x = std::move(x0);
  Eigen::VectorXd g;
  r.value = f(r.x, &g);
  r.evaluations = 1;
  const double g0 = g.norm();
  if (g0 == 0.0) {
    r.converged = true;
    return r;
  }
  std::deque<Pair> mem;
  Eigen::VectorXd xNew, gNew;
  for (r.iterations = 0; r.iterations < options.maxIterations;) {
    Eigen::VectorXd d = direction(mem, g);
    double slope = g.dot(d);
    if (!(slope < 0.0)) {  // lost descent through rounding: restart from steepest descent
      mem.clear();
      d = -g;
      slope = -g.squaredNorm();
    }
    double t = 1.0;
    if (mem.empty()) {
      const double maxStep = options.firstStepMaxNorm > 0.0 ? options.firstStepMaxNorm : 1.0;
      t = maxStep / d.cwiseAbs().maxCoeff();
    }
    // Weak Wolfe by bracketing (Lewis & Overton): halve on failed decrease, double on too
    // steep a slope, bisect once bracketed.
    double lo = 0.0, hi = std::numeric_limits<double>::infinity();
    double fNew = 0.0;
    bool accepted = false;
    for (int ls = 0; ls < options.maxLineSearchSteps; ++ls) {
      xNew = r.x + t * d;
      fNew = f(xNew, &gNew);
      ++r.evaluations;
      if (!std::isfinite(fNew) || fNew > r.value + options.armijo * t * slope) {
        hi = t;
      } else if (gNew.dot(d) < options.wolfe * slope) {
        lo = t;
      } else {
        accepted = true;
        break;
      }
      t = std::isinf(hi) ? 2.0 * t : 0.5 * (lo + hi);
    }
    if (!accepted) {
      // Keep a bracketed point that decreased f rather than nothing.
      if (lo > 0.0) {
        xNew = r.x + lo * d;
        fNew = f(xNew, &gNew);
        ++r.evaluations;
      } else {
        return r;
      }
    }
    ++r.iterations;
    const double decrease = r.value - fNew;
    Pair p{xNew - r.x, gNew - g, 0.0};
    const double sy = p.s.dot(p.y);
    r.x.swap(xNew);
    g.swap(gNew);
    r.value = fNew;
    if (sy > 1e-12 * p.s.norm() * p.y.norm()) {  // skip pairs that would break positivity
      p.rho = 1.0 / sy;
      mem.push_back(std::move(p));
      if (static_cast<int>(mem.size()) > options.memory) mem.pop_front();
    }
    if (g.norm() <= options.gradientTolerance * g0 ||
        decrease <= options.valueTolerance * std::abs(r.value)) {
      r.converged = true;
      break;
    }
  }
  return r;
}

}  // namespace bcassim
