#include "bcassim/assimilation/SigmaPointSet.h"

#include <fmt/format.h>

#include <stdexcept>

#include "bcassim/Error.h"
#include "bcassim/assimilation/CanonicalSigmaPoints.h"
#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/assimilation/SimplexSigmaPoints.h"
#include "bcassim/assimilation/StarSigmaPoints.h"

namespace bcassim {

SigmaPointKind parseSigmaPointKind(std::string_view name) {
  if (name == "star") return SigmaPointKind::Star;
  if (name == "canonical") return SigmaPointKind::Canonical;
  if (name == "simplex") return SigmaPointKind::Simplex;
  throw InputError(
      fmt::format("unknown sigma points '{}': expected star, canonical or simplex", name));
}

Eigen::MatrixXd SigmaPointSet::points(const Eigen::VectorXd& mean,
                                      const Eigen::MatrixXd& sqrtCov) const {
  if (sqrtCov.cols() != unit.rows() || sqrtCov.rows() != mean.size())
    throw std::invalid_argument("SigmaPointSet::points: factor and mean do not fit the set");
  const Eigen::Index r = unit.rows(), s = unit.cols();
  Eigen::MatrixXd X(mean.size(), s);
  switch (structure) {
    case UnitStructure::Dense:
      X.noalias() = sqrtCov * unit;
      break;
    case UnitStructure::SignedColumns:
      for (Eigen::Index k = 0; k < s; ++k) {
        const Eigen::Index row = nonzeroRow[static_cast<size_t>(k)];
        if (row < 0)
          X.col(k).setZero();
        else
          X.col(k) = unit(row, k) * sqrtCov.col(row);
      }
      break;
    case UnitStructure::Simplex: {
      // Column k = sum over rows i >= k of c_(i+1) S_i, plus -k c_k S_(k-1): suffix sums.
      Eigen::VectorXd suffix = Eigen::VectorXd::Zero(X.rows());
      for (Eigen::Index k = s - 1; k >= 0; --k) {
        if (k < r) suffix += unit(k, 0) * sqrtCov.col(k);
        X.col(k) = suffix;
        if (k >= 1) X.col(k) += unit(k - 1, k) * sqrtCov.col(k - 1);
      }
      break;
    }
  }
  X.colwise() += mean;
  return X;
}

Eigen::MatrixXd SigmaPointSet::covarianceOf(const Eigen::MatrixXd& X) const {
  const Eigen::MatrixXd D = X.colwise() - meanOf(X);
  Eigen::MatrixXd P;
  weightedGram(D, weights, P);
  return P;
}

SigmaPointSet makeSigmaPoints(SigmaPointKind kind, Eigen::Index n) {
  switch (kind) {
    case SigmaPointKind::Star:
      return starSigmaPoints(n);
    case SigmaPointKind::Canonical:
      return canonicalSigmaPoints(n);
    case SigmaPointKind::Simplex:
      return simplexSigmaPoints(n);
  }
  return simplexSigmaPoints(n);
}

}  // namespace bcassim
