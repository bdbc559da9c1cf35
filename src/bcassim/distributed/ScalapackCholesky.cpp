#include "bcassim/distributed/ScalapackCholesky.h"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#include <vector>

#include "bcassim/Stopwatch.h"
#include "bcassim/distributed/MpiSession.h"

// BLACS (C interface) and ScaLAPACK (Fortran) of Debian's libscalapack-openmpi.
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

// Columns and rows of a block: large enough for BLAS 3 in each panel (128 beat 32, 64 and 256
// for n = 2,791 on 2 ranks), small enough that n of a few thousand spreads over 8-64 ranks.
constexpr int kBlock = 128;

using Descriptor = std::array<int, 9>;

Descriptor describe(int n, int block, int context, int localRows) {
  Descriptor d{};
  const int zero = 0, lld = std::max(1, localRows);
  int info = 0;
  descinit_(d.data(), &n, &n, &block, &block, &zero, &zero, &context, &lld, &info);
  if (info != 0) throw std::runtime_error(fmt::format("ScaLAPACK descinit: argument {}", -info));
  return d;
}

}  // namespace

ScalapackCholesky::ScalapackCholesky(int ranks) : ranks_(ranks), block_(kBlock) {}

// The grid as square as the ranks allow (rows <= columns).
void ScalapackCholesky::makeGrids() {
  rows_ = 1;
  for (int r = 1; r * r <= ranks_; ++r)
    if (ranks_ % r == 0) rows_ = r;
  cols_ = ranks_ / rows_;
  Cblacs_get(-1, 0, &grid_);
  Cblacs_gridinit(&grid_, "Row", rows_, cols_);
  Cblacs_gridinfo(grid_, &rows_, &cols_, &myRow_, &myCol_);
  gridsMade_ = true;
}

// Rank `rank`'s block-cyclic piece of an n x n column-major matrix: its local matrix (rows x
// cols, column-major) holds the blocks (I, J) with I = its grid row, J = its grid column modulo
// the grid. visit(offset in the whole matrix, offset in the piece, length) for every column
// segment of a block that reaches the lower triangle (pdpotrf("L") reads no other).
template <typename Visit>
void ScalapackCholesky::forEachSegment(int n, int rank, Visit&& visit) const {
  const int zero = 0;
  int prow = 0, pcol = 0;
  Cblacs_pcoord(grid_, rank, &prow, &pcol);
  const int rows = numroc_(&n, &block_, &prow, &zero, &rows_);
  const int cols = numroc_(&n, &block_, &pcol, &zero, &cols_);
  for (int lj = 0; lj < cols; ++lj) {
    const int gj = (lj / block_ * cols_ + pcol) * block_ + lj % block_;
    for (int li = 0; li < rows; li += block_) {
      const int gi = (li / block_ * rows_ + prow) * block_;
      const int length = std::min(block_, rows - li);
      if (gi + length - 1 < gj) continue;  // above the diagonal
      visit(static_cast<size_t>(gj) * n + gi, static_cast<size_t>(lj) * rows + li, length);
    }
  }
}

bool ScalapackCholesky::factor(int n, const double* A, double* L) {
  // MPI counts and offsets are int: n^2 entries must fit.
  if (static_cast<long long>(n) * n > std::numeric_limits<int>::max())
    throw std::runtime_error(fmt::format(
        "a covariance of {} rows is too large to share over MPI (n^2 over 2^31 entries)", n));
  if (!gridsMade_) makeGrids();
  const int zero = 0, one = 1;
  const bool isRoot = A != nullptr;
  const int localRows = numroc_(&n, &block_, &myRow_, &zero, &rows_);
  const int localCols = numroc_(&n, &block_, &myCol_, &zero, &cols_);
  std::vector<double>& local = local_;
  local.resize(static_cast<size_t>(std::max(1, localRows)) *
               static_cast<size_t>(std::max(1, localCols)));
  const Descriptor distributed = describe(n, block_, grid_, localRows);

  // Every rank's piece packed on rank 0 and scattered (pdgemr2d moves element by element, ~4x
  // slower measured).
  const Clock::time_point start = Clock::now();
  std::vector<int> counts(static_cast<size_t>(ranks_)), offsets(static_cast<size_t>(ranks_));
  for (int r = 0, offset = 0; r < ranks_; ++r) {
    int prow = 0, pcol = 0;
    Cblacs_pcoord(grid_, r, &prow, &pcol);
    counts[static_cast<size_t>(r)] =
        numroc_(&n, &block_, &prow, &zero, &rows_) * numroc_(&n, &block_, &pcol, &zero, &cols_);
    offsets[static_cast<size_t>(r)] = offset;
    offset += counts[static_cast<size_t>(r)];
  }
  std::vector<double>& packed = packed_;
  if (isRoot) {
    packed.resize(static_cast<size_t>(offsets.back()) + static_cast<size_t>(counts.back()));
    for (int r = 0; r < ranks_; ++r) {
      double* piece = packed.data() + offsets[static_cast<size_t>(r)];
      forEachSegment(n, r, [&](size_t whole, size_t local, int length) {
        std::copy(A + whole, A + whole + length, piece + local);
      });
    }
  }
  lastPackSeconds_ = secondsSince(start);
  checkMpi(MPI_Scatterv(packed.data(), counts.data(), offsets.data(), MPI_DOUBLE, local.data(),
                        localRows * localCols, MPI_DOUBLE, 0, MPI_COMM_WORLD),
           "sending the covariance's blocks to the ranks");
  const Clock::time_point scattered = Clock::now();
  int info = 0;
  pdpotrf_("L", &n, local.data(), &one, &one, distributed.data(), &info);
  const Clock::time_point factored = Clock::now();
  lastFactorSeconds_ = secondsBetween(scattered, factored);
  lastMoveSeconds_ = secondsBetween(start, scattered);
  if (info < 0) throw std::runtime_error(fmt::format("ScaLAPACK pdpotrf: argument {}", -info));
  if (info > 0) return false;
  checkMpi(MPI_Gatherv(local.data(), localRows * localCols, MPI_DOUBLE, packed.data(),
                       counts.data(), offsets.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD),
           "gathering the Cholesky factor's blocks");
  const Clock::time_point gathered = Clock::now();
  if (isRoot)
    for (int r = 0; r < ranks_; ++r) {
      const double* piece = packed.data() + offsets[static_cast<size_t>(r)];
      forEachSegment(n, r, [&](size_t whole, size_t local, int length) {
        std::copy(piece + local, piece + local + length, L + whole);
      });
    }
  lastPackSeconds_ += secondsSince(gathered);
  lastMoveSeconds_ += secondsSince(factored);
  lastRootBytes_ = isRoot ? 2.0 * 8.0 * (offsets.back() + counts.back() - counts[0]) : 0.0;
  return true;
}

}  // namespace bcassim
