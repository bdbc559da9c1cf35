// Limited-memory BFGS with a weak-Wolfe line search, minimising the registration objective of
// thesis eq. 4.7 over the initial momenta (any smooth objective in fact).
#pragma once
#include <Eigen/Core>
#include <functional>

namespace bcassim {

struct LbfgsOptions {
  int memory = 10;  // stored (s, y) pairs
  int maxIterations = 200;
  int maxLineSearchSteps = 40;
  double gradientTolerance = 1e-6;  // stop when |g| <= tol * |g0|
  double valueTolerance = 1e-9;     // stop when an iteration decreases f by < tol * |f|
  double armijo = 1e-4;             // sufficient decrease constant c1
  double wolfe = 0.9;               // curvature constant c2
  double firstStepMaxNorm = 0.0;    // max-norm of the first trial step; <= 0: 1
};

struct LbfgsResult {
  Eigen::VectorXd x;
  double value = 0.0;
  int iterations = 0;
  int evaluations = 0;
  bool converged = false;  // a tolerance was met (not the iteration cap or a failed line search)
};

// f(x, grad) returns the value at x and writes the gradient (resized) into *grad.
using LbfgsObjective = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd* grad)>;

LbfgsResult minimizeLbfgs(const LbfgsObjective& f, Eigen::VectorXd x0,
                          const LbfgsOptions& options = {});

}  // namespace bcassim
