// Creates a linear solver from its name in a scene file: cg, jacobi-pcg, cholmod, factorized-pcg.
#pragma once
#include <memory>
#include <string_view>

#include "bcassim/mechanics/solvers/FactorizedPcgSolver.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

// policy configures factorized-pcg; its relTol is also the tolerance of cg and jacobi-pcg.
// `analysis` (optional): a factor whose symbolic analysis the factorising solvers (cholmod,
// factorized-pcg) start from, for a matrix of its pattern (another is analysed anew).
// Throws InputError for an unknown name.
std::unique_ptr<LinearSolver> makeLinearSolver(std::string_view name,
                                               const RefreshPolicy& policy = {},
                                               const CholeskyFactor* analysis = nullptr);

}  // namespace bcassim
