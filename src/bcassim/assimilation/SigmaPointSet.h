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

// The set of `kind` in dimension n >= 1 (star with its default kappa).
SigmaPointSet makeSigmaPoints(SigmaPointKind kind, Eigen::Index n);

}  // namespace bcassim
