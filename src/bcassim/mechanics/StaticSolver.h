// Static equilibrium f_int(x) = f_ext by Newton-Raphson with a backtracking line search on the
// total potential energy, and load stepping (loads and prescribed displacements in increments); an
// increment that fails is redone as two of half the size.
#pragma once
#include <memory>

#include "bcassim/mechanics/ChunkedForces.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/StepFailure.h"
#include "bcassim/mechanics/solvers/AndersonMixing.h"
#include "bcassim/mechanics/solvers/LinearSolver.h"

namespace bcassim {

struct StaticOptions {
  // Newton stops at |f_int - f_ext| <= max(relativeTolerance * max(|f_ext|, |f_int at the
  // increment's first iterate|), the round-off of f_int (forceRoundOff)).
  double relativeTolerance = 1e-10;
  int maxIterations = 50;  // Newton iterations per load increment
  int loadSteps = 1;       // loads applied in this many equal increments
  // A load increment that fails (Newton not converged in maxIterations, a line search without an
  // acceptable step, an inverted element, a failed linear solve) is redone from its start as two
  // of half the size, recursively, while they stay at least this fraction of a load step's
  // increment: 1/64 allows six halvings, 1 none (the scene's time.min_dt / time.dt).
  double minIncrementFraction = 1.0 / 64.0;
};

struct StaticReport {
  bool converged = false;   // true whenever solve() returns: it throws StepFailure otherwise
  int iterations = 0;       // Newton iterations, total over load increments (failed ones included)
  int retries = 0;          // load increments that failed and were redone as two halves
  double residualNorm = 0;  // N, |f_int - f_ext| on the free dofs at the end
  double initialResidualNorm = 0;  // N, the same at the start (chordSolve)
  double tolerance = 0;            // N, the residual aimed at (chordSolve)
};

// The chord steps a chordSolve that stopped short would still need to reach its tolerance, at the
// contraction its steps had on average; INT_MAX where it did not contract or cannot tell (fewer
// than two steps).
int chordStepsToGo(const StaticReport& report);

class StaticSolver {
 public:
  StaticSolver(const MechanicalModel& model, std::unique_ptr<LinearSolver> solver,
               StaticOptions options = {});
  // Solves for equilibrium under the loads and prescribed displacements at time t, starting from
  // x. Prescribed displacements ramp from x's values, loads from those of the last solve that
  // returned (none before the first, see continueFrom): call it with the previous solution, as a
  // time loop does. Throws StepFailure when an increment of the smallest size fails too.
  StaticReport solve(const MechanicalModel& model, double t, Eigen::VectorXd& x);
  // The next solve starts from an equilibrium under the loads at time t (a resumed run).
  void continueFrom(const MechanicalModel& model, double t);
  // Factorises the tangent at x once, computing nothing that is kept: the factorisation's plan
  // and memory are then made, and the first solve (a filter's first frame) does not pay for them.
  // A tangent that cannot be factorised is left for that solve to meet.
  void warmUp(const MechanicalModel& model, double t, const Eigen::VectorXd& x);
  // The next solve starts from an equilibrium under the external forces `load` (N, 3N; empty:
  // none, the rest state), e.g. a filter's forecasts that all start from the analysed mean.
  void continueFromLoad(Eigen::VectorXd load) { equilibriumLoad_ = std::move(load); }
  // Chord (modified Newton) iterations towards the equilibrium at time t with a tangent frozen
  // elsewhere (FrozenTangent::buildStatic, at another state or other parameters), the springs'
  // own stiffness restored by its low-rank correction: steps A^-1 (f_ext(t) - f_int(x)), loads
  // at once (no ramp), prescribed displacements reached by the first step. Later steps are
  // Anderson-mixed (AndersonMixing) and kept only where they lower the residual, else the plain
  // step, halved down to a quarter. Stops converged at Newton's tolerance; stops not converged
  // after maxIterations steps or when no step lowers the residual, leaving x at the last iterate
  // (its residual in the report) for the caller to finish with solve(). maxIterations = 1 makes
  // one linearised step, a filter's sigma point about its mean, whose residual is not evaluated
  // (the report's is the start's). Throws InvertedElementError if x has an inverted element at
  // the start, after the prescribed motion or after that single step; the caller falls back to
  // solve() from its start.
  // singlePrecision: each step solves with the factor rounded to float (FrozenTangent::solve);
  // the iterations converge to the same equilibrium, the residual being computed in double.
  // threads >= 1: the force assemblies and the single-precision solves are split over that many
  // threads (ChunkedForces, CholeskyFactor::Workspace::setThreads), with the same iterates for
  // any count; 0: the serial kernels on this thread.
  StaticReport chordSolve(const MechanicalModel& model, double t, Eigen::VectorXd& x,
                          const FrozenTangent& tangent, int maxIterations,
                          bool singlePrecision = false, int threads = 0);
  // More steps of the last chordSolve, from where it stopped (x, t and tangent as they were left),
  // its Anderson history kept: a chord that is contracting but ran out of steps goes on as one.
  StaticReport continueChord(const MechanicalModel& model, double t, Eigen::VectorXd& x,
                             const FrozenTangent& tangent, int maxIterations,
                             bool singlePrecision = false, int threads = 0);
  // The relative tolerance of the solves from now on (StaticOptions::relativeTolerance): looser
  // for an equilibrium that only serves as a linearisation point.
  double relativeTolerance() const { return options_.relativeTolerance; }
  void setRelativeTolerance(double tolerance) { options_.relativeTolerance = tolerance; }
  // The solver of the Newton systems (to share a factorisation between workers).
  LinearSolver& linearSolver() { return *solver_; }
  // The tangent the last solve() leaves at its equilibrium `at` (the x it returned, at its t):
  // K assembled there (its last convergence check) and the factor of its last Newton iteration's
  // K, one step before, shared with the solver: a static mean tangent there without another
  // factorisation. Null where that solve made no factorisation, its last was regularised (K
  // was not positive definite), or its linear solver keeps no exact factor (only cholmod does).
  std::shared_ptr<const FrozenTangent> newtonTangent(const MechanicalModel& model,
                                                     const MechanicalState& at) const;

 private:
  struct Increments;
  void factorizeRegularized(const MechanicalModel& model);
  void solveIncrement(Increments& run, double from, double to);
  void newton(Increments& run, double lambda);
  StaticReport chordIterations(const MechanicalModel& model, double t, Eigen::VectorXd& x,
                               const FrozenTangent& tangent, int maxIterations,
                               bool singlePrecision, int threads, bool continuing);

  std::unique_ptr<LinearSolver> solver_;
  StaticOptions options_;
  SparseMatrix K_;
  Eigen::VectorXd equilibriumLoad_;   // f_ext the last solve ended at (N); empty before the first
  bool factorizedUnshifted_ = false;  // the solver's last factorisation was of K itself
  bool newtonTangentReady_ = false;   // ... and made by the last solve, which returned
  Eigen::VectorXd chordFext_, chordFint_, chordRhs_, chordDx_, chordKnown_, chordTrial_, chordG_;
  AndersonMixing chordMixing_;
  CholeskyFactor::Workspace chordWork_;       // threads 0
  CholeskyFactor::Workspace chordSplitWork_;  // threads >= 1, with chordChunks_
  std::unique_ptr<ChunkedForces> chordChunks_;
};

}  // namespace bcassim
