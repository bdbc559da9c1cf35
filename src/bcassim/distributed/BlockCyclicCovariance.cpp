#include "bcassim/distributed/BlockCyclicCovariance.h"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "bcassim/Blas.h"
#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/distributed/MpiSession.h"

// BLACS (C interface) and ScaLAPACK of Debian's libscalapack-openmpi / OpenBLAS.
extern "C" {
void Cblacs_get(int context, int what, int* value);
void Cblacs_gridinit(int* context, const char* order, int rows, int cols);
void Cblacs_gridinfo(int context, int* rows, int* cols, int* myRow, int* myCol);
void Cblacs_pcoord(int context, int process, int* row, int* col);
int numroc_(const int* n, const int* nb, const int* iproc, const int* isrcproc, const int* nprocs);
void descinit_(int* desc, const int* m, const int* n, const int* mb, const int* nb,
               const int* irsrc, const int* icsrc, const int* context, const int* lld, int* info);
void pdpotrf_(const char* uplo, const int* n, double* a, const int* ia, const int* ja,
              const int* desca, int* info);
}

namespace bcassim {

namespace {

// Rows and columns of a block: large enough for BLAS 3 in each panel (128 beat 32, 64 and 256
// for n = 2,791 on 2 ranks), small enough that n of a few thousand spreads over 8-64 ranks.
constexpr int kBlock = 128;

int allMin(int value) {
  int out = value;
  checkMpi(MPI_Allreduce(&value, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD),
           "agreeing on the covariance's state");
  return out;
}

double allSum(double value) {
  double out = value;
  checkMpi(MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD),
           "summing the covariance's diagonal");
  return out;
}

// C (m x n, leading dimension ldc) = alpha A B^T-or-not + beta C on the system BLAS.
void gemm(const char* ta, const char* tb, int m, int n, int k, double alpha, const double* A,
          int lda, const double* B, int ldb, double beta, double* C, int ldc) {
  if (m == 0 || n == 0) return;
  dgemm_(ta, tb, &m, &n, &k, &alpha, A, &lda, B, &ldb, &beta, C, &ldc);
}

}  // namespace

BlockCyclicCovariance::BlockCyclicCovariance(int ranks, int n)
    : ranks_(ranks), n_(n), block_(kBlock) {
  if (static_cast<long long>(n) * n > std::numeric_limits<int>::max())
    throw std::runtime_error(fmt::format(
        "a covariance of {} rows is too large to share over MPI (n^2 over 2^31 entries)", n));
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  // The grid as square as the ranks allow (rows <= columns).
  for (int r = 1; r * r <= ranks_; ++r)
    if (ranks_ % r == 0) gridRows_ = r;
  gridCols_ = ranks_ / gridRows_;
  Cblacs_get(-1, 0, &grid_);
  Cblacs_gridinit(&grid_, "Row", gridRows_, gridCols_);
  for (int r = 0; r < ranks_; ++r) pieces_.push_back(describe(r));
  long long total = 0;
  for (const Piece& p : pieces_) {
    packedCounts_.push_back(static_cast<int>(p.packedSize));
    packedOffsets_.push_back(static_cast<int>(total));
    total += p.packedSize;
  }
  const Piece& mine = pieces_[static_cast<size_t>(rank_)];
  packed_.setZero(mine.packedSize);
  local_.setZero(std::max(1, mine.localRows()), std::max(1, mine.localCols()));
  // This rank's diagonal entries: where they sit in the packed piece.
  for (int lj = 0; lj < mine.localCols(); ++lj) {
    const int j = mine.globalCol[static_cast<size_t>(lj)];
    const auto row = std::lower_bound(mine.globalRow.begin(), mine.globalRow.end(), j);
    if (row == mine.globalRow.end() || *row != j) continue;
    diagonalIndex_.push_back(j);
    diagonalAt_.push_back(mine.offset[static_cast<size_t>(lj)] + (row - mine.globalRow.begin()) -
                          mine.rowStart[static_cast<size_t>(lj)]);
  }
  const int zero = 0, lld = std::max(1, mine.localRows());
  int info = 0;
  descinit_(descriptor_.data(), &n_, &n_, &block_, &block_, &zero, &zero, &grid_, &lld, &info);
  if (info != 0) throw std::runtime_error(fmt::format("ScaLAPACK descinit: argument {}", -info));
}

BlockCyclicCovariance::Piece BlockCyclicCovariance::describe(int rank) const {
  Piece p;
  Cblacs_pcoord(grid_, rank, &p.gridRow, &p.gridCol);
  const int zero = 0;
  const int rows = numroc_(&n_, &block_, &p.gridRow, &zero, &gridRows_);
  const int cols = numroc_(&n_, &block_, &p.gridCol, &zero, &gridCols_);
  for (int li = 0; li < rows; ++li)
    p.globalRow.push_back((li / block_ * gridRows_ + p.gridRow) * block_ + li % block_);
  for (int lj = 0; lj < cols; ++lj)
    p.globalCol.push_back((lj / block_ * gridCols_ + p.gridCol) * block_ + lj % block_);
  // A column of block J keeps the rows of blocks I >= J: a tail of the local rows (pdpotrf("L")
  // reads no block above the diagonal; the diagonal block is kept whole).
  for (int lj = 0; lj < cols; ++lj) {
    const int J = p.globalCol[static_cast<size_t>(lj)] / block_;
    const int k = J > p.gridRow ? (J - p.gridRow + gridRows_ - 1) / gridRows_ : 0;
    p.rowStart.push_back(std::min(k * block_, rows));
    p.offset.push_back(p.packedSize);
    p.packedSize += rows - p.rowStart.back();
  }
  return p;
}

void BlockCyclicCovariance::scatter(const double* P) {
  if (rank_ == 0) {
    sendBuffer_.resize(packedOffsets_.back() + packedCounts_.back());
    for (int r = 0; r < ranks_; ++r) {
      const Piece& p = pieces_[static_cast<size_t>(r)];
      double* out = sendBuffer_.data() + packedOffsets_[static_cast<size_t>(r)];
      for (int lj = 0; lj < p.localCols(); ++lj) {
        const long long j = p.globalCol[static_cast<size_t>(lj)];
        for (int li = p.rowStart[static_cast<size_t>(lj)]; li < p.localRows(); ++li) {
          const long long i = p.globalRow[static_cast<size_t>(li)];
          *out++ = i >= j ? P[j * n_ + i] : P[i * n_ + j];  // the lower triangle
        }
      }
    }
  }
  checkMpi(
      MPI_Scatterv(sendBuffer_.data(), packedCounts_.data(), packedOffsets_.data(), MPI_DOUBLE,
                   packed_.data(), static_cast<int>(packed_.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD),
      "sending the covariance's pieces to the ranks");
}

void BlockCyclicCovariance::gather(double* P) const {
  if (rank_ == 0) sendBuffer_.resize(packedOffsets_.back() + packedCounts_.back());
  checkMpi(
      MPI_Gatherv(packed_.data(), static_cast<int>(packed_.size()), MPI_DOUBLE, sendBuffer_.data(),
                  packedCounts_.data(), packedOffsets_.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD),
      "gathering the covariance's pieces");
  if (rank_ != 0) return;
  for (int r = 0; r < ranks_; ++r) {
    const Piece& p = pieces_[static_cast<size_t>(r)];
    const double* in = sendBuffer_.data() + packedOffsets_[static_cast<size_t>(r)];
    for (int lj = 0; lj < p.localCols(); ++lj) {
      const long long j = p.globalCol[static_cast<size_t>(lj)];
      for (int li = p.rowStart[static_cast<size_t>(lj)]; li < p.localRows(); ++li, ++in) {
        const long long i = p.globalRow[static_cast<size_t>(li)];
        if (i >= j) P[j * n_ + i] = P[i * n_ + j] = *in;
      }
    }
  }
}

Eigen::VectorXd BlockCyclicCovariance::diagonal() const {
  Eigen::VectorXd mine = Eigen::VectorXd::Zero(n_), all(rank_ == 0 ? n_ : 0);
  for (size_t k = 0; k < diagonalAt_.size(); ++k) mine(diagonalIndex_[k]) = packed_(diagonalAt_[k]);
  // Each entry is held by one rank: the sum adds zeros to it, exactly.
  checkMpi(MPI_Reduce(mine.data(), all.data(), n_, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD),
           "gathering the covariance's diagonal");
  return all;
}

void BlockCyclicCovariance::addToDiagonal(const Eigen::VectorXd& q) {
  if (q.size() != n_) throw std::invalid_argument("BlockCyclicCovariance: one entry per row");
  for (size_t k = 0; k < diagonalAt_.size(); ++k) packed_(diagonalAt_[k]) += q(diagonalIndex_[k]);
}

void BlockCyclicCovariance::unpackToLocal(const Eigen::VectorXd& packed) {
  const Piece& p = pieces_[static_cast<size_t>(rank_)];
  for (int lj = 0; lj < p.localCols(); ++lj) {
    const int start = p.rowStart[static_cast<size_t>(lj)];
    local_.col(lj).segment(start, p.localRows() - start) =
        packed.segment(p.offset[static_cast<size_t>(lj)], p.localRows() - start);
  }
}

void BlockCyclicCovariance::factor(RepairLog& log) {
  const Piece& p = pieces_[static_cast<size_t>(rank_)];
  if (allMin(packed_.allFinite() ? 1 : 0) == 0)
    throw NumericalError("covariance has non-finite entries");
  const std::vector<long long>& diagonal = diagonalAt_;
  const int one = 1;
  lastFactorSeconds_ = 0;
  const auto tryFactor = [&](const Eigen::VectorXd& packed) {
    unpackToLocal(packed);
    const Clock::time_point start = Clock::now();
    int status = 0;
    pdpotrf_("L", &n_, local_.data(), &one, &one, descriptor_.data(), &status);
    lastFactorSeconds_ += secondsSince(start);
    if (status < 0)
      throw std::runtime_error(fmt::format("ScaLAPACK pdpotrf: argument {}", -status));
    return allMin(status == 0 ? 1 : 0) == 1;
  };
  // As choleskyWithRepair: a diagonal entry <= 0 goes straight to the repair.
  bool positive = true;
  for (const long long at : diagonal) positive = positive && packed_(at) > 0.0;
  bool done = allMin(positive ? 1 : 0) == 1 && tryFactor(packed_);
  if (!done) {
    double absSum = 0;
    for (const long long at : diagonal) absSum += std::abs(packed_(at));
    const double scale = n_ > 0 ? std::max(allSum(absSum) / n_, 1e-300) : 1.0;
    Eigen::VectorXd S = packed_;
    double added = 0.0;
    for (double jitter = 1e-10 * scale; jitter <= 1e10 * scale && !done; jitter *= 10) {
      for (const long long at : diagonal) S(at) += jitter - added;
      added = jitter;
      if (tryFactor(S)) {
        done = true;
        ++log.repairs;
        log.largestJitter = std::max(log.largestJitter, jitter);
      }
    }
    if (!done)
      throw NumericalError("covariance is not positive definite and jitter did not repair it");
  }
  // The diagonal blocks' upper parts still hold P: zero, so that the piece is L alone.
  for (int lj = 0; lj < p.localCols(); ++lj) {
    const int j = p.globalCol[static_cast<size_t>(lj)];
    for (int li = p.rowStart[static_cast<size_t>(lj)];
         li < p.localRows() && p.globalRow[static_cast<size_t>(li)] < j; ++li)
      local_(li, lj) = 0.0;
  }
}

void BlockCyclicCovariance::factorColumns(const std::vector<std::vector<Eigen::Index>>& needed,
                                          Eigen::MatrixXd& columns) const {
  if (static_cast<int>(needed.size()) != ranks_)
    throw std::invalid_argument("BlockCyclicCovariance::factorColumns: one list per rank");
  const Piece& me = pieces_[static_cast<size_t>(rank_)];
  // The first local row of `p` at or below global row j.
  const auto firstRow = [](const Piece& p, int j) {
    return static_cast<int>(std::lower_bound(p.globalRow.begin(), p.globalRow.end(), j) -
                            p.globalRow.begin());
  };
  std::vector<int> sendCounts(static_cast<size_t>(ranks_), 0), recvCounts = sendCounts;
  std::vector<char> wanted(static_cast<size_t>(n_), 0);
  // Sized first: the buffers are kept between steps (no fresh pages to fault in each step).
  long long total = 0;
  for (int d = 0; d < ranks_; ++d)
    for (const Eigen::Index j : needed[static_cast<size_t>(d)]) {
      const auto at = std::lower_bound(me.globalCol.begin(), me.globalCol.end(), j);
      if (at != me.globalCol.end() && *at == j) total += me.localRows() - firstRow(me, *at);
    }
  if (sendBuffer_.size() < total) sendBuffer_.resize(total);
  double* out = sendBuffer_.data();
  for (int d = 0; d < ranks_; ++d) {
    for (const Eigen::Index j : needed[static_cast<size_t>(d)]) wanted[static_cast<size_t>(j)] = 1;
    const double* before = out;
    for (int lj = 0; lj < me.localCols(); ++lj) {
      const int j = me.globalCol[static_cast<size_t>(lj)];
      if (!wanted[static_cast<size_t>(j)]) continue;
      const int first = firstRow(me, j);
      const double* column = local_.data() + static_cast<long long>(lj) * local_.rows();
      out = std::copy(column + first, column + me.localRows(), out);
    }
    sendCounts[static_cast<size_t>(d)] = static_cast<int>(out - before);
    for (const Eigen::Index j : needed[static_cast<size_t>(d)]) wanted[static_cast<size_t>(j)] = 0;
  }
  const std::vector<Eigen::Index>& mine = needed[static_cast<size_t>(rank_)];
  std::vector<int> position(static_cast<size_t>(n_), -1);
  for (size_t k = 0; k < mine.size(); ++k)
    position[static_cast<size_t>(mine[k])] = static_cast<int>(k);
  for (int s = 0; s < ranks_; ++s) {
    const Piece& p = pieces_[static_cast<size_t>(s)];
    for (const int j : p.globalCol)
      if (position[static_cast<size_t>(j)] >= 0)
        recvCounts[static_cast<size_t>(s)] += p.localRows() - firstRow(p, j);
  }
  std::vector<int> sendOffsets(static_cast<size_t>(ranks_), 0), recvOffsets = sendOffsets;
  for (int r = 1; r < ranks_; ++r) {
    sendOffsets[static_cast<size_t>(r)] =
        sendOffsets[static_cast<size_t>(r - 1)] + sendCounts[static_cast<size_t>(r - 1)];
    recvOffsets[static_cast<size_t>(r)] =
        recvOffsets[static_cast<size_t>(r - 1)] + recvCounts[static_cast<size_t>(r - 1)];
  }
  const long long received =
      static_cast<long long>(recvOffsets.back()) + static_cast<long long>(recvCounts.back());
  if (receiveBuffer_.size() < received) receiveBuffer_.resize(received);
  checkMpi(MPI_Alltoallv(sendBuffer_.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE,
                         receiveBuffer_.data(), recvCounts.data(), recvOffsets.data(), MPI_DOUBLE,
                         MPI_COMM_WORLD),
           "handing the covariance factor's columns to the ranks");
  columns.setZero(n_, static_cast<Eigen::Index>(mine.size()));
  const double* at = receiveBuffer_.data();
  for (int s = 0; s < ranks_; ++s) {
    const Piece& p = pieces_[static_cast<size_t>(s)];
    for (const int j : p.globalCol) {
      const int k = position[static_cast<size_t>(j)];
      if (k < 0) continue;
      // The source's rows come in runs of consecutive global rows (its row blocks).
      for (int li = firstRow(p, j); li < p.localRows();) {
        const int row = p.globalRow[static_cast<size_t>(li)];
        const int run = std::min(p.localRows() - li, block_ - li % block_);
        std::copy(at, at + run, columns.col(k).data() + row);
        at += run;
        li += run;
      }
    }
  }
}

Eigen::VectorXd BlockCyclicCovariance::factorSuffixSum(const std::vector<Eigen::Index>& from,
                                                       const Eigen::VectorXd& coefficient) const {
  if (static_cast<int>(from.size()) != ranks_ || coefficient.size() != n_)
    throw std::invalid_argument("BlockCyclicCovariance::factorSuffixSum: sizes");
  const Piece& p = pieces_[static_cast<size_t>(rank_)];
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(p.localCols(), ranks_);
  for (int lj = 0; lj < p.localCols(); ++lj) {
    const int j = p.globalCol[static_cast<size_t>(lj)];
    for (int r = 0; r < ranks_; ++r)
      if (j >= from[static_cast<size_t>(r)]) V(lj, r) = coefficient(j);
  }
  const Eigen::MatrixXd Y =
      local_.topLeftCorner(p.localRows(), p.localCols()) * V;  // rows of this piece
  Eigen::MatrixXd whole = Eigen::MatrixXd::Zero(n_, ranks_);
  for (int li = 0; li < p.localRows(); ++li)
    whole.row(p.globalRow[static_cast<size_t>(li)]) = Y.row(li);
  Eigen::VectorXd mine(n_);
  checkMpi(
      MPI_Reduce_scatter_block(whole.data(), mine.data(), n_, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD),
      "summing the covariance factor's columns");
  return mine;
}

void BlockCyclicCovariance::assignGram(const Eigen::MatrixXd& D, const Eigen::VectorXd& w) {
  if (D.rows() != n_ || D.cols() != w.size())
    throw std::invalid_argument("BlockCyclicCovariance::assignGram: sizes");
  const Clock::time_point start = Clock::now();
  const int c = static_cast<int>(D.cols());
  // Equal weights (simplex points) are BLAS's alpha; others scale a copy of D's columns.
  const bool equal = c > 0 && (w.array() == w(0)).all();
  Eigen::MatrixXd scaled;
  if (!equal && c > 0) scaled = D * w.asDiagonal();
  const double alpha = equal ? w(0) : 1.0;
  const double* B = equal ? D.data() : scaled.data();
  sendBuffer_.resize(packedOffsets_.back() + packedCounts_.back());
  for (int d = 0; d < ranks_; ++d) {
    const Piece& p = pieces_[static_cast<size_t>(d)];
    double* out = sendBuffer_.data() + packedOffsets_[static_cast<size_t>(d)];
    // One product per block of the lower triangle, D's rows read in place (a block's rows are
    // consecutive in the whole matrix), written where the packed piece keeps it.
    for (int lj = 0; lj < p.localCols(); lj += block_) {
      const int width = std::min(block_, p.localCols() - lj);
      const int first = p.rowStart[static_cast<size_t>(lj)];
      const int tail = p.localRows() - first;
      double* C = out + p.offset[static_cast<size_t>(lj)];
      if (c == 0) {
        std::fill(C, C + static_cast<long long>(tail) * width, 0.0);
        continue;
      }
      const int column = p.globalCol[static_cast<size_t>(lj)];
      for (int li = first; li < p.localRows(); li += block_) {
        const int rows = std::min(block_, p.localRows() - li);
        gemm("N", "T", rows, width, c, alpha, D.data() + p.globalRow[static_cast<size_t>(li)], n_,
             B + column, n_, 0.0, C + (li - first), std::max(1, tail));
      }
    }
  }
  const Clock::time_point products = Clock::now();
  lastGramProductSeconds_ = secondsBetween(start, products);
  checkMpi(MPI_Reduce_scatter(sendBuffer_.data(), packed_.data(), packedCounts_.data(), MPI_DOUBLE,
                              MPI_SUM, MPI_COMM_WORLD),
           "adding the ranks' Gram matrices into the covariance's pieces");
  lastGramReduceSeconds_ = secondsSince(products);
}

void BlockCyclicCovariance::subtractGram(const Eigen::MatrixXd& G) {
  if (G.cols() != n_) throw std::invalid_argument("BlockCyclicCovariance::subtractGram: sizes");
  const Piece& p = pieces_[static_cast<size_t>(rank_)];
  const int k = static_cast<int>(G.rows());
  if (k == 0) return;
  Eigen::MatrixXd Grows(k, p.localRows());
  for (int li = 0; li < p.localRows(); ++li)
    Grows.col(li) = G.col(p.globalRow[static_cast<size_t>(li)]);
  for (int lj = 0; lj < p.localCols(); lj += block_) {
    const int width = std::min(block_, p.localCols() - lj);
    const int start = p.rowStart[static_cast<size_t>(lj)];
    const int tail = p.localRows() - start;
    gemm("T", "N", tail, width, k, -1.0, Grows.data() + static_cast<long long>(start) * k, k,
         G.data() + static_cast<long long>(p.globalCol[static_cast<size_t>(lj)]) * k, k, 1.0,
         packed_.data() + p.offset[static_cast<size_t>(lj)], std::max(1, tail));
  }
}

}  // namespace bcassim
