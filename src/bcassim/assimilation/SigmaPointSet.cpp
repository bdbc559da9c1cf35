#include "bcassim/assimilation/SigmaPointSet.h"

#include <fmt/format.h>

#include <algorithm>
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

SigmaPointColumns compactColumns(const SigmaPointSet& set) {
  if (set.structure == UnitStructure::Dense)
    throw std::logic_error("compactColumns: a dense unit matrix has no compact form");
  const Eigen::Index r = set.unit.rows(), s = set.unit.cols();
  SigmaPointColumns c;
  c.structure = set.structure;
  c.rows = r;
  c.ownCoefficient.setZero(s);
  c.ownRow.assign(static_cast<size_t>(s), -1);
  if (set.structure == UnitStructure::Simplex) {
    c.suffixCoefficient = set.unit.col(0);
    for (Eigen::Index k = 1; k < s; ++k) {
      c.ownRow[static_cast<size_t>(k)] = k - 1;
      c.ownCoefficient(k) = set.unit(k - 1, k);
    }
  } else {
    for (Eigen::Index k = 0; k < s; ++k) {
      const Eigen::Index row = set.nonzeroRow[static_cast<size_t>(k)];
      c.ownRow[static_cast<size_t>(k)] = row;
      if (row >= 0) c.ownCoefficient(k) = set.unit(row, k);
    }
  }
  return c;
}

std::vector<Eigen::Index> SigmaPointColumns::factorColumns(Eigen::Index first,
                                                           Eigen::Index count) const {
  std::vector<Eigen::Index> out;
  if (count <= 0) return out;
  if (structure == UnitStructure::Simplex) {
    // Column k reads S_(k-1) and S_k.. S_(r-1); the suffix past the block stands for the rest.
    for (Eigen::Index i = std::max<Eigen::Index>(first - 1, 0); i < std::min(first + count, rows);
         ++i)
      out.push_back(i);
    return out;
  }
  for (Eigen::Index k = first; k < first + count; ++k)
    if (ownRow[static_cast<size_t>(k)] >= 0) out.push_back(ownRow[static_cast<size_t>(k)]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Eigen::MatrixXd SigmaPointColumns::points(const Eigen::VectorXd& mean, Eigen::Index first,
                                          Eigen::Index count, const Eigen::MatrixXd& columns,
                                          const Eigen::VectorXd& suffix) const {
  const std::vector<Eigen::Index> read = factorColumns(first, count);
  if (columns.cols() != static_cast<Eigen::Index>(read.size()) || columns.rows() != mean.size())
    throw std::invalid_argument("SigmaPointColumns::points: the factor's columns do not fit");
  // Where factor column i sits in `columns`.
  const auto at = [&](Eigen::Index i) {
    return std::lower_bound(read.begin(), read.end(), i) - read.begin();
  };
  Eigen::MatrixXd X(mean.size(), count);
  if (structure == UnitStructure::Simplex) {
    if (suffix.size() != mean.size())
      throw std::invalid_argument("SigmaPointColumns::points: simplex points need the suffix");
    Eigen::VectorXd sum = suffix;
    for (Eigen::Index k = first + count - 1; k >= first; --k) {
      if (k < rows) sum += suffixCoefficient(k) * columns.col(at(k));
      X.col(k - first) = sum;
      if (k >= 1) X.col(k - first) += ownCoefficient(k) * columns.col(at(k - 1));
    }
  } else {
    for (Eigen::Index k = first; k < first + count; ++k) {
      const Eigen::Index row = ownRow[static_cast<size_t>(k)];
      if (row < 0)
        X.col(k - first).setZero();
      else
        X.col(k - first) = ownCoefficient(k) * columns.col(at(row));
    }
  }
  X.colwise() += mean;
  return X;
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
