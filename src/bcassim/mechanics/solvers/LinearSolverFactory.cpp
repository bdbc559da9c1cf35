#include "bcassim/mechanics/solvers/LinearSolverFactory.h"

#include <string>

#include "bcassim/Error.h"
#include "bcassim/mechanics/solvers/CgSolver.h"
#include "bcassim/mechanics/solvers/CholmodSolver.h"
#include "bcassim/mechanics/solvers/JacobiPcgSolver.h"

namespace bcassim {

std::unique_ptr<LinearSolver> makeLinearSolver(std::string_view name, const RefreshPolicy& policy,
                                               const CholeskyFactor* analysis) {
  auto analysed = [&] {
    return analysis && analysis->isAnalyzed() ? analysis->cloneAnalysis() : nullptr;
  };
  if (name == "cg") return std::make_unique<CgSolver>(policy.relTol);
  if (name == "jacobi-pcg") return std::make_unique<JacobiPcgSolver>(policy.relTol);
  if (name == "cholmod") return std::make_unique<CholmodSolver>(analysed());
  if (name == "factorized-pcg") return std::make_unique<FactorizedPcgSolver>(analysed(), policy);
  throw InputError("unknown linear solver '" + std::string(name) +
                   "'; expected one of cg, jacobi-pcg, cholmod, factorized-pcg");
}

}  // namespace bcassim
