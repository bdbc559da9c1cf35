// A symmetric n x n matrix (a full-state UKF's covariance) kept by every rank of MPI_COMM_WORLD in
// ScaLAPACK's block-cyclic pieces, its lower triangle only, from one step to the next: a Gram
// matrix summed over the ranks lands straight in the pieces (one reduce-scatter), the Cholesky
// factor is computed in place (pdpotrf), the Kalman update P -= G^T G is applied piece by piece,
// and each rank is handed the factor's columns it needs. No rank holds the whole matrix unless
// asked for it. Every method is collective: all ranks call it, in the same order, with the same
// arguments (except where one says rank 0).
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "bcassim/assimilation/CovarianceRepair.h"

namespace bcassim {

class BlockCyclicCovariance {
 public:
  // The pieces of an n x n matrix over `ranks` ranks (a process grid as square as they allow),
  // all zero. Throws std::runtime_error if n^2 entries do not fit MPI's int counts.
  BlockCyclicCovariance(int ranks, int n);

  int size() const { return n_; }

  // P = `P`, given on rank 0 (n x n, its lower triangle read; other ranks pass null).
  void scatter(const double* P);
  // The whole P (symmetric) into `P` on rank 0 (n x n; other ranks pass null).
  void gather(double* P) const;
  // diag(P) on rank 0 (other ranks: an empty vector).
  Eigen::VectorXd diagonal() const;
  // P += diag(q), q (n entries) the same on every rank.
  void addToDiagonal(const Eigen::VectorXd& q);

  // The lower Cholesky factor of P kept beside it, repaired as choleskyWithRepair does (the same
  // jitters; `log` the same on every rank). Throws NumericalError on every rank if P is not
  // finite or no jitter helps.
  void factor(RepairLog& log);
  // After factor(): the factor's columns needed[this rank] (ascending) into `columns` (n x
  // count, zero above the diagonal), needed[r] listing those of rank r.
  void factorColumns(const std::vector<std::vector<Eigen::Index>>& needed,
                     Eigen::MatrixXd& columns) const;
  // After factor(): for rank r, sum over columns i >= from[r] (i < n) of coefficient(i) L_i;
  // returns this rank's (n entries).
  Eigen::VectorXd factorSuffixSum(const std::vector<Eigen::Index>& from,
                                  const Eigen::VectorXd& coefficient) const;

  // P = the sum over the ranks of D diag(w) D^T, D (n x c) and w (c >= 0 entries) each rank's.
  void assignGram(const Eigen::MatrixXd& D, const Eigen::VectorXd& w);
  // P -= G^T G, G (k x n) the same on every rank.
  void subtractGram(const Eigen::MatrixXd& G);

  // Keeps P as it is / puts the kept one back (no communication).
  void keep() { kept_ = packed_; }
  void restore() { packed_ = kept_; }

  // Wall seconds of the last factor()'s pdpotrf calls, of the last assignGram()'s local products
  // and reduce-scatter, for the cost model.
  double lastFactorSeconds() const { return lastFactorSeconds_; }
  double lastGramProductSeconds() const { return lastGramProductSeconds_; }
  double lastGramReduceSeconds() const { return lastGramReduceSeconds_; }

 private:
  // One rank's piece: its rows and columns of the whole matrix, and where each local column's
  // lower part (rows from its column block's diagonal block down) sits in the packed piece.
  struct Piece {
    int gridRow = 0, gridCol = 0;
    std::vector<int> globalRow, globalCol;  // of each local row / column, ascending
    std::vector<int> rowStart;              // per local column: its first packed local row
    std::vector<long long> offset;          // per local column: its start in the packed piece
    long long packedSize = 0;
    int localRows() const { return static_cast<int>(globalRow.size()); }
    int localCols() const { return static_cast<int>(globalCol.size()); }
  };
  Piece describe(int rank) const;
  void unpackToLocal(const Eigen::VectorXd& packed);

  int ranks_, n_, rank_ = 0;
  int block_;
  int grid_ = -1, gridRows_ = 1, gridCols_ = 1;
  std::vector<Piece> pieces_;  // every rank's
  std::vector<int> packedCounts_, packedOffsets_;
  std::vector<int> diagonalIndex_;     // this rank's diagonal entries (global index)
  std::vector<long long> diagonalAt_;  // and where they sit in the packed piece
  std::array<int, 9> descriptor_{};    // ScaLAPACK's for the local piece
  Eigen::VectorXd packed_, kept_;      // this rank's lower piece, packed
  Eigen::MatrixXd local_;              // this rank's factor (ScaLAPACK's local layout)
  mutable Eigen::VectorXd sendBuffer_, receiveBuffer_;  // kept between steps
  double lastFactorSeconds_ = 0, lastGramProductSeconds_ = 0, lastGramReduceSeconds_ = 0;
};

}  // namespace bcassim
