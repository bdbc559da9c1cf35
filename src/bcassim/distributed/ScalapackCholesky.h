// The Cholesky factor of a matrix held by rank 0, computed by every rank of MPI_COMM_WORLD
// together: ScaLAPACK's pdpotrf on a block-cyclic process grid, so that a full-state UKF's
// n^3 / 3 flops per step are shared instead of waiting on rank 0.
#pragma once
#include <vector>

namespace bcassim {

class ScalapackCholesky {
 public:
  explicit ScalapackCholesky(int ranks);

  // Collective over MPI_COMM_WORLD: every rank calls it, in the same order, with the same n.
  // On rank 0, `A` (n x n, column-major, symmetric: its lower triangle is read) is factored into
  // `L` (n x n, lower triangle written, upper left as it was); other ranks pass null. Returns, on
  // every rank, false if A is not (numerically) positive definite. Throws std::runtime_error if
  // ScaLAPACK reports an argument error.
  bool factor(int n, const double* A, double* L);

  // Bytes rank 0 sent to and received from the grid in the last factor() (its share of A, L).
  double lastRootBytes() const { return lastRootBytes_; }
  // Wall seconds of the last factor() in moving A out and L back (of which rank 0's packing and
  // unpacking of the pieces), and in pdpotrf itself.
  double lastMoveSeconds() const { return lastMoveSeconds_; }
  double lastPackSeconds() const { return lastPackSeconds_; }
  double lastFactorSeconds() const { return lastFactorSeconds_; }

 private:
  void makeGrids();
  template <typename Visit>
  void forEachSegment(int n, int rank, Visit&& visit) const;

  int ranks_;
  int block_;  // rows and columns of a block
  bool gridsMade_ = false;
  int grid_ = -1;  // the pr x pc grid of every rank
  int rows_ = 1, cols_ = 1, myRow_ = 0, myCol_ = 0;
  std::vector<double> local_, packed_;  // this rank's piece; on rank 0 every rank's, packed
  double lastRootBytes_ = 0, lastMoveSeconds_ = 0, lastPackSeconds_ = 0;
  double lastFactorSeconds_ = 0;
};

}  // namespace bcassim
