#include "bcassim/mechanics/FrozenTangent.h"

#include <algorithm>
#include <stdexcept>

#include "bcassim/Stopwatch.h"
#include "bcassim/mechanics/ImplicitEulerSystem.h"

namespace bcassim {
namespace {

// Calls visit(j, d, w) for every entry of U: column j = 3 s + c (spring s, component c), row d
// (a dof of the spring's tet), weight w; Dirichlet dofs are skipped when `eliminated`.
template <class Visit>
void forEachSpringEntry(const MechanicalModel& model, bool eliminated, Visit&& visit) {
  const auto& springs = model.springs.springs();
  const auto& fixed = model.dirichlet.constrainedDofs();  // sorted
  for (size_t s = 0; s < springs.size(); ++s)
    for (int a = 0; a < 4; ++a) {
      const int node = model.mesh->T(springs[s].tet, a);
      for (int c = 0; c < 3; ++c) {
        const int d = 3 * node + c;
        if (eliminated && std::binary_search(fixed.begin(), fixed.end(), d)) continue;
        visit(3 * static_cast<Eigen::Index>(s) + c, d, springs[s].weights(a));
      }
    }
}

}  // namespace

Eigen::VectorXd springGather(const MechanicalModel& model, const Eigen::VectorXd& v,
                             bool eliminated) {
  Eigen::VectorXd out =
      Eigen::VectorXd::Zero(3 * static_cast<Eigen::Index>(model.springs.springs().size()));
  forEachSpringEntry(model, eliminated,
                     [&](Eigen::Index j, int d, double w) { out(j) += w * v(d); });
  return out;
}

void springScatterAdd(const MechanicalModel& model, const Eigen::VectorXd& q, bool eliminated,
                      Eigen::VectorXd& out) {
  forEachSpringEntry(model, eliminated,
                     [&](Eigen::Index j, int d, double w) { out(d) += w * q(j); });
}

Eigen::VectorXd blockDiagonalTimes(const Eigen::MatrixXd& D, const Eigen::VectorXd& v) {
  Eigen::VectorXd out(v.size());
  for (Eigen::Index b = 0; b < D.rows(); b += 3)
    out.segment<3>(b) = D.middleRows<3>(b) * v.segment<3>(b);
  return out;
}

Eigen::MatrixXd FrozenTangent::springChange(const MechanicalModel& model, const Eigen::VectorXd& x,
                                            double t) const {
  if (!correctsSprings()) return {};
  const size_t springs = springBlocks_.size();
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(springs), 3);
  for (size_t k = 0; k < springs; ++k)
    D.block<3, 3>(3 * static_cast<Eigen::Index>(k), 0) =
        model.springs.attachmentStiffness(*model.mesh, x, t, k) - springBlocks_[k];
  return D;
}

void FrozenTangent::solve(const Eigen::MatrixXd& D, const Eigen::VectorXd& b, Eigen::VectorXd& y,
                          CholeskyFactor::Workspace& work, bool singlePrecision) const {
  if (D.size() == 0 || !D.any()) {
    if (singlePrecision)
      factor_->solveSinglePrecision(b, y, work);
    else
      factor_->solve(b, y, work);
    return;
  }
  // Woodbury between the sweeps (springGram): w = (I + c D G)^-1 c D W^T z, z -= W w.
  const double c = stiffnessScale_;
  Eigen::MatrixXd system = Eigen::MatrixXd::Identity(G_.rows(), G_.cols());
  for (Eigen::Index k = 0; k < D.rows(); k += 3)
    system.middleRows<3>(k) += c * D.middleRows<3>(k) * G_.middleRows<3>(k);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(system);
  factor_->solveWithMidCorrection(b, y, work, singlePrecision, [&](Eigen::VectorXd& z) {
    Eigen::VectorXd onPaths(static_cast<Eigen::Index>(springRows_.size()));
    for (size_t r = 0; r < springRows_.size(); ++r)
      onPaths(static_cast<Eigen::Index>(r)) = z(springRows_[r]);
    const Eigen::VectorXd w = lu.solve(c * blockDiagonalTimes(D, W_.transpose() * onPaths));
    onPaths.noalias() = W_ * w;
    for (size_t r = 0; r < springRows_.size(); ++r)
      z(springRows_[r]) -= onPaths(static_cast<Eigen::Index>(r));
  });
}

void FrozenTangent::moveKnownSpringColumns(const MechanicalModel& model, const Eigen::MatrixXd& D,
                                           const Eigen::VectorXd& known, Eigen::VectorXd& b) const {
  if (D.size() == 0 || !D.any() || !known.any()) return;
  Eigen::VectorXd moved = Eigen::VectorXd::Zero(b.size());
  springScatterAdd(model, blockDiagonalTimes(D, springGather(model, known, false)), false, moved);
  b -= stiffnessScale_ * moved;
}

std::shared_ptr<const FrozenTangent> FrozenTangent::build(const MechanicalModel& model,
                                                          const MechanicalState& state, double dt,
                                                          const CholeskyFactor* analysis,
                                                          int threads) {
  return assemble(model, state, dt, false, analysis, threads);
}

std::shared_ptr<const FrozenTangent> FrozenTangent::buildStatic(const MechanicalModel& model,
                                                                const MechanicalState& state,
                                                                const CholeskyFactor* analysis,
                                                                int threads) {
  return assemble(model, state, 0.0, true, analysis, threads);
}

std::shared_ptr<const FrozenTangent> FrozenTangent::assemble(const MechanicalModel& model,
                                                             const MechanicalState& state,
                                                             double dt, bool isStatic,
                                                             const CholeskyFactor* analysis,
                                                             int threads) {
  const auto start = Clock::now();
  auto t = std::make_shared<FrozenTangent>();
  t->static_ = isStatic;
  t->dt_ = dt;
  t->stiffnessScale_ = isStatic ? 1.0 : implicitEulerStiffnessScale(model, dt);
  Eigen::VectorXd f;
  model.internalForcesAndStiffness(state.t, state.x, f, t->K_);
  t->diagonalNorm_ = t->K_.diagonal().norm();
  if (!isStatic) {
    t->A_ = t->K_;
    stiffnessToImplicitEulerMatrix(model, dt, t->A_);
  }
  SparseMatrix eliminated = t->systemMatrix();
  model.dirichlet.eliminateMatrix(eliminated);
  const auto assembled = Clock::now();
  if (analysis != nullptr && analysis->isAnalyzed() && analysis->matchesPattern(eliminated)) {
    t->factor_ = analysis->cloneAnalysis();
  } else {
    t->factor_ = std::make_shared<CholeskyFactor>();
    t->factor_->analyzePattern(eliminated);
  }
  t->factor_->factorize(eliminated, threads);
  const auto factorized = Clock::now();

  t->prepareSpringCorrection(model, state);
  const auto end = Clock::now();
  t->assemblySeconds_ = secondsBetween(start, assembled);
  t->factorizationSeconds_ = secondsBetween(assembled, factorized);
  t->springSeconds_ = secondsBetween(factorized, end);
  t->buildSeconds_ = secondsBetween(start, end);
  return t;
}

std::shared_ptr<const FrozenTangent> FrozenTangent::fromFactor(
    const MechanicalModel& model, const MechanicalState& state, const SparseMatrix& K,
    std::shared_ptr<CholeskyFactor> factor) {
  if (!factor || !factor->isFactorized())
    throw std::invalid_argument("FrozenTangent::fromFactor: needs a factorised factor");
  const auto start = Clock::now();
  auto t = std::make_shared<FrozenTangent>();
  t->static_ = true;
  t->stiffnessScale_ = 1.0;
  t->K_ = K;
  t->diagonalNorm_ = t->K_.diagonal().norm();
  t->factor_ = std::move(factor);
  t->prepareSpringCorrection(model, state);
  t->springSeconds_ = t->buildSeconds_ = secondsSince(start);
  return t;
}

// W = L^-1 P U and G = W^T W for the springs' low-rank correction, and their blocks H_s at
// `state` (none beyond kMaxCorrectedSprings springs).
void FrozenTangent::prepareSpringCorrection(const MechanicalModel& model,
                                            const MechanicalState& state) {
  const auto& springs = model.springs.springs();
  if (springs.empty() || static_cast<int>(springs.size()) > kMaxCorrectedSprings) return;
  const auto n = static_cast<Eigen::Index>(state.x.size());
  const auto r = 3 * static_cast<Eigen::Index>(springs.size());
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(n, r);
  forEachSpringEntry(model, true, [&](Eigen::Index j, int d, double w) { U(d, j) += w; });
  factor_->forwardSolve(U, springRows_, W_);
  G_.noalias() = W_.transpose() * W_;
  for (size_t s = 0; s < springs.size(); ++s)
    springBlocks_.push_back(model.springs.attachmentStiffness(*model.mesh, state.x, state.t, s));
}

}  // namespace bcassim
