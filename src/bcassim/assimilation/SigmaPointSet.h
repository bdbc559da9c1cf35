// Unit sigma points I^(k) and weights w_k (thesis eq. 3.3-3.6) with sum w_k I^(k) = 0 and
// sum w_k I^(k) I^(k)^T = Id, so that x + S I^(k) with S S^T = P reproduces mean x and covariance
// P.
#pragma once
#include <Eigen/Core>
#include <string_view>
#include <vector>

namespace bcassim {

enum class SigmaPointKind {
  Star,       // 2n+1 points, eq. 3.4 (centre first)
  Canonical,  // 2n points, eq. 3.5
  Simplex,    // n+1 points, eq. 3.6
};

// Parses "star", "canonical" or "simplex"; throws InputError otherwise.
SigmaPointKind parseSigmaPointKind(std::string_view name);

// What points() may exploit instead of a dense product with `unit` (O(n^2) instead of O(n^3) for
// a full-state filter with thousands of entries).
enum class UnitStructure {
  Dense,          // any unit matrix
  SignedColumns,  // at most one nonzero per column (star, canonical): its row in nonzeroRow
  Simplex,        // eq. 3.6: row j-1 holds c_j in columns 0..j-1 and -j c_j in column j
};

struct SigmaPointSet {
  Eigen::MatrixXd unit;     // n x s: column k is I^(k)
  Eigen::VectorXd weights;  // s weights, summing to 1
  UnitStructure structure = UnitStructure::Dense;
  // SignedColumns: the row of each column's nonzero entry, -1 for a zero column.
  std::vector<Eigen::Index> nonzeroRow;

  Eigen::Index count() const { return unit.cols(); }
  // n x s points mean + sqrtCov * I^(k); sqrtCov is any n x r factor with r = unit.rows().
  Eigen::MatrixXd points(const Eigen::VectorXd& mean, const Eigen::MatrixXd& sqrtCov) const;
  // Weighted mean and weighted covariance of the columns of X.
  Eigen::VectorXd meanOf(const Eigen::MatrixXd& X) const { return X * weights; }
  Eigen::MatrixXd covarianceOf(const Eigen::MatrixXd& X) const;
};

// A structured set's unit matrix in O(n + s) numbers: what forming some columns of points() from
// only the factor's columns they read takes (distributed/ hands it to processes that form their
// own sigma points from their share of a distributed factor). Not for UnitStructure::Dense.
struct SigmaPointColumns {
  UnitStructure structure = UnitStructure::Simplex;
  Eigen::Index rows = 0;              // r = unit.rows()
  Eigen::VectorXd suffixCoefficient;  // Simplex: unit(i, 0), i < r (the suffix sums' terms)
  Eigen::VectorXd ownCoefficient;     // per column k: Simplex unit(k-1, k), else unit(row, k)
  std::vector<Eigen::Index> ownRow;   // per column k: the factor column of that term, -1 none

  // The factor's columns that points k in [first, first + count) read, ascending.
  std::vector<Eigen::Index> factorColumns(Eigen::Index first, Eigen::Index count) const;
  // Points [first, first + count) of SigmaPointSet::points(mean, S): `columns` holds the factor
  // S's columns factorColumns(first, count) in that order, and, for Simplex, `suffix` the sum
  // over i >= first + count (i < r) of suffixCoefficient(i) S_i (empty otherwise).
  Eigen::MatrixXd points(const Eigen::VectorXd& mean, Eigen::Index first, Eigen::Index count,
                         const Eigen::MatrixXd& columns, const Eigen::VectorXd& suffix) const;
};

// The set's SigmaPointColumns; throws std::logic_error for a Dense set.
SigmaPointColumns compactColumns(const SigmaPointSet& set);

// The set of `kind` in dimension n >= 1 (star with its default kappa).
SigmaPointSet makeSigmaPoints(SigmaPointKind kind, Eigen::Index n);

}  // namespace bcassim
