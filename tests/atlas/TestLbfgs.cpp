// L-BFGS with weak-Wolfe line search: minimisers of Rosenbrock and of an ill-conditioned quadratic.
#include <gtest/gtest.h>

#include "bcassim/Error.h"
#include "bcassim/atlas/Lbfgs.h"

namespace bcassim {
namespace {

TEST(Lbfgs, FindsRosenbrockMinimum) {
  const auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
    const double a = 1.0 - x(0), b = x(1) - x(0) * x(0);
    *g = Eigen::Vector2d(-2.0 * a - 400.0 * x(0) * b, 200.0 * b);
    return a * a + 100.0 * b * b;
  };
  LbfgsOptions o;
  o.gradientTolerance = 1e-10;
  o.valueTolerance = 0.0;
  const LbfgsResult r = minimizeLbfgs(f, Eigen::Vector2d(-1.2, 1.0), o);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x(0), 1.0, 1e-6);
  EXPECT_NEAR(r.x(1), 1.0, 1e-6);
  EXPECT_LT(r.iterations, 100);
}

TEST(Lbfgs, SolvesIllConditionedQuadratic) {
  const int n = 50;
  Eigen::VectorXd diag(n), b(n);
  for (int i = 0; i < n; ++i) {
    diag(i) = std::pow(10.0, 4.0 * i / (n - 1));  // condition number 1e4
    b(i) = std::sin(i + 1.0);
  }
  const auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
    *g = diag.cwiseProduct(x) - b;
    return 0.5 * x.dot(diag.cwiseProduct(x)) - b.dot(x);
  };
  LbfgsOptions o;
  o.gradientTolerance = 1e-10;
  o.valueTolerance = 0.0;
  o.maxIterations = 1000;
  const LbfgsResult r = minimizeLbfgs(f, Eigen::VectorXd::Zero(n), o);
  EXPECT_TRUE(r.converged);
  // Armijo cannot see decreases below the rounding of f, so x is resolved to ~sqrt(eps) only.
  EXPECT_LT((r.x - b.cwiseQuotient(diag)).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Lbfgs, RejectsBadOptions) {
  LbfgsOptions o;
  o.wolfe = 1e-5;
  const auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
    *g = x;
    return 0.5 * x.squaredNorm();
  };
  EXPECT_THROW(minimizeLbfgs(f, Eigen::VectorXd::Ones(2), o), InputError);
}

}  // namespace
}  // namespace bcassim
