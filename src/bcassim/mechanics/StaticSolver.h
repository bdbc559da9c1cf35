// Static equilibrium f_int(x) = f_ext by Newton-Raphson with a backtracking line search on the
// total potential energy, and optional load stepping (loads and prescribed displacements scaled).
#pragma once
#include <memory>

#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

struct StaticOptions {
  double relativeTolerance = 1e-10;  // on |f_int - f_ext| / max(|f_ext|, |f_int at first iterate|)
  int maxIterations = 50;            // Newton iterations per load step
  int loadSteps = 1;                 // loads applied in this many equal increments
};

struct StaticReport {
  bool converged = false;
  int iterations = 0;       // total over load steps
  double residualNorm = 0;  // N, at the end
};

class StaticSolver {
 public:
  StaticSolver(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
               StaticOptions options = {});
  // Solves for equilibrium under the loads and prescribed displacements at time t, starting from x.
  StaticReport solve(const MechanicalModel& model, double t, Eigen::VectorXd& x);

 private:
  void factorizeRegularized(const MechanicalModel& model);

  std::unique_ptr<LinearSolver> solver_;
  StaticOptions options_;
  SparseMatrix K_;
};

}  // namespace bcassim
