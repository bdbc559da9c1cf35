// The implicit-Euler matrix (or, for static frames, the stiffness) of one linearisation point,
// factorised once and shared read-only by many solves: the W of a linearly implicit
// (Rosenbrock-W) Euler step or the K of a chord (modified Newton) step, e.g. the tangent at a
// Kalman filter's mean used by all of its sigma points. The ligament springs, whose stiffness the
// estimated parameters change, can be made each step's own by a low-rank correction.
#pragma once
#include <memory>
#include <vector>

#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/solvers/CholeskyFactor.h"

namespace bcassim {

class FrozenTangent {
 public:
  // Springs beyond this many get no correction (3 columns each in L^-1 P U).
  static constexpr int kMaxCorrectedSprings = 128;

  // Assembles K at (state.x, state.t) with the model as it is now (its parameters included),
  // forms A = (1 + dt zeta_M) M + (dt zeta_K + dt^2) K (eq. 2.16) and factorises A with the
  // Dirichlet dofs eliminated. With up to kMaxCorrectedSprings springs it also prepares their
  // correction (see stepWithTangent). `analysis`, if given, is a factor whose symbolic analysis
  // of the model's pattern is reused. dt in s. Throws NumericalError if A is not positive
  // definite, InvertedElementError if an element is inverted at state.x.
  // `threads`: the factorisation's (CholeskyFactor::factorize; the same result for any count).
  static std::shared_ptr<const FrozenTangent> build(const MechanicalModel& model,
                                                    const MechanicalState& state, double dt,
                                                    const CholeskyFactor* analysis = nullptr,
                                                    int threads = 1);
  // The same for static equilibria: A = K (stiffnessScale() 1, dt() 0), for
  // StaticSolver::chordSolve. Throws NumericalError if K is not positive definite.
  static std::shared_ptr<const FrozenTangent> buildStatic(const MechanicalModel& model,
                                                          const MechanicalState& state,
                                                          const CholeskyFactor* analysis = nullptr,
                                                          int threads = 1);
  // A static tangent from a factorisation made already: K assembled at (state.x, state.t) and the
  // factor of eliminated K at a point near it (a Newton solve's last iteration, one step before
  // its equilibrium), shared, not copied (K is). Chord steps with it converge as with
  // buildStatic's; the springs' correction is made here as there.
  static std::shared_ptr<const FrozenTangent> fromFactor(const MechanicalModel& model,
                                                         const MechanicalState& state,
                                                         const SparseMatrix& K,
                                                         std::shared_ptr<CholeskyFactor> factor);
  bool isStatic() const { return static_; }

  double dt() const { return dt_; }
  // Multiplier of K in A: dt zeta_K + dt^2 (1 for a static tangent).
  double stiffnessScale() const { return stiffnessScale_; }
  // K at the linearisation point (N/m), with the pattern's structure.
  const SparseMatrix& stiffness() const { return K_; }
  // |diag K| (N/m), for the round-off floor of a residual (forceRoundOff).
  double stiffnessDiagonalNorm() const { return diagonalNorm_; }
  // A before Dirichlet elimination: its constrained columns move known values to a right-hand side.
  // A static tangent's is K itself (not stored twice).
  const SparseMatrix& systemMatrix() const { return static_ ? K_ : A_; }
  // Factor of A with the Dirichlet rows and columns eliminated.
  const CholeskyFactor& factor() const { return *factor_; }
  // Seconds spent building (assembly, factorisation, spring correction), for timings.
  double buildSeconds() const { return buildSeconds_; }
  // The parts of buildSeconds(): stiffness assembly and system matrix, numerical factorisation,
  // the spring correction (L^-1 P U by a forward block solve along the springs' paths, G).
  double assemblySeconds() const { return assemblySeconds_; }
  double factorizationSeconds() const { return factorizationSeconds_; }
  double springSeconds() const { return springSeconds_; }

  // The springs' part of the stiffness as a low-rank term U blockdiag(H_s) U^T: column 3s + c of
  // U spreads component c of spring s's attachment to its tet's nodes by the barycentric weights
  // (rows of Dirichlet dofs zero). A step whose springs have blocks H_s' solves
  // (A + h U D U^T) y = b with D = blockdiag(H_s' - H_s), h = stiffnessScale(), by Woodbury:
  // y = A^-1 b - A^-1 U (I + h D G)^-1 h D U^T A^-1 b, G = U^T A^-1 U. With A = P^T L L^T P and
  // W = L^-1 P U (non-zero only on the springs' elimination-tree paths, so cheap to build):
  // G = W^T W, U^T A^-1 b = W^T c and y = P^T L^-T (c - W w) with c = L^-1 P b, so a step costs
  // one solve plus a few products with W, and A^-1 U is never formed.
  bool correctsSprings() const { return !springBlocks_.empty(); }
  const std::vector<Mat3>& springBlocks() const { return springBlocks_; }  // H_s, N/m
  const Eigen::MatrixXd& springGram() const { return G_; }                 // G, 3S x 3S

  // D = blockdiag(H_s' - H_s) stacked as 3S x 3 blocks: the springs of `model` at (x, t) against
  // the tangent's (empty without correction).
  Eigen::MatrixXd springChange(const MechanicalModel& model, const Eigen::VectorXd& x,
                               double t) const;
  // y = (A + c U D U^T)^-1 b on the eliminated system (b already eliminated), D from
  // springChange (empty or zero: A^-1 b), c = stiffnessScale(). singlePrecision: A^-1 through
  // the factor rounded to float (CholeskyFactor::solveSinglePrecision, ~1e-3 relative on a
  // liver): half the memory traffic, for iterations that correct their own error (chords).
  void solve(const Eigen::MatrixXd& D, const Eigen::VectorXd& b, Eigen::VectorXd& y,
             CholeskyFactor::Workspace& work, bool singlePrecision = false) const;
  // b -= c U D U^T known (known: a full-length vector, zero but on constrained dofs): the
  // springs' share of the constrained columns, before eliminateRightHandSide.
  void moveKnownSpringColumns(const MechanicalModel& model, const Eigen::MatrixXd& D,
                              const Eigen::VectorXd& known, Eigen::VectorXd& b) const;

 private:
  static std::shared_ptr<const FrozenTangent> assemble(const MechanicalModel& model,
                                                       const MechanicalState& state, double dt,
                                                       bool isStatic,
                                                       const CholeskyFactor* analysis, int threads);
  void prepareSpringCorrection(const MechanicalModel& model, const MechanicalState& state);

  bool static_ = false;
  double diagonalNorm_ = 0;
  double dt_ = 0, stiffnessScale_ = 0, buildSeconds_ = 0;
  double assemblySeconds_ = 0, factorizationSeconds_ = 0, springSeconds_ = 0;
  SparseMatrix K_, A_;  // A_ empty when static_ (A = K)
  std::shared_ptr<CholeskyFactor> factor_;
  std::vector<Mat3> springBlocks_;
  std::vector<int> springRows_;  // the rows of L that W can have non-zero
  Eigen::MatrixXd W_, G_;        // W on springRows_ (|springRows_| x 3S), G = W^T W
};

// U^T v for the springs of `model` (3 entries per spring), skipping Dirichlet dofs when
// `eliminated` (the U of the eliminated system).
Eigen::VectorXd springGather(const MechanicalModel& model, const Eigen::VectorXd& v,
                             bool eliminated);
// out += U q (U as above; Dirichlet rows left alone when `eliminated`).
void springScatterAdd(const MechanicalModel& model, const Eigen::VectorXd& q, bool eliminated,
                      Eigen::VectorXd& out);
// blockdiag(D_0, D_1, ...) v for D stacked as (3k x 3) blocks.
Eigen::VectorXd blockDiagonalTimes(const Eigen::MatrixXd& D, const Eigen::VectorXd& v);

}  // namespace bcassim
