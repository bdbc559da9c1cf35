#include "bcassim/assimilation/SigmaPointSet.h"

#include <fmt/format.h>

#include "bcassim/Error.h"
#include "bcassim/assimilation/CanonicalSigmaPoints.h"
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
  Eigen::MatrixXd X = sqrtCov * unit;
  X.colwise() += mean;
  return X;
}

Eigen::MatrixXd SigmaPointSet::covarianceOf(const Eigen::MatrixXd& X) const {
  const Eigen::MatrixXd D = X.colwise() - meanOf(X);
  return D * weights.asDiagonal() * D.transpose();
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
