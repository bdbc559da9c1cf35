// The full-state UKF's dense algebra on R ranks, for the MPI executor's cost model
// (docs/benchmarks.md §8): the Gram matrix of S deviations of n rows and the Cholesky factor of
// an n x n covariance, alone (R = 1: the system BLAS/LAPACK, as the threaded filter runs them)
// or shared as `assimilate --mpi` shares them (SharedGram.h, ScalapackCholesky.h), with the
// bare MPI_Reduce of the n x n matrix's lower triangle. Medians of 5 after one warm-up; the shared
// results are checked against rank 0's own (largest entry difference over the largest entry).
// Usage: mpirun -np R bench_dense_algebra [n=2791] [S=2792]
#include <mpi.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/distributed/ScalapackCholesky.h"
#include "bcassim/distributed/SharedGram.h"

namespace {

double medianSeconds(const std::function<void()>& run) {
  std::vector<double> times;
  for (int repeat = 0; repeat < 6; ++repeat) {
    MPI_Barrier(MPI_COMM_WORLD);
    const double start = MPI_Wtime();
    run();
    MPI_Barrier(MPI_COMM_WORLD);
    if (repeat > 0) times.push_back(MPI_Wtime() - start);
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  return times[times.size() / 2];
}

double normwiseDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int n = argc > 1 ? std::atoi(argv[1]) : 2791;
  const int S = argc > 2 ? std::atoi(argv[2]) : 2792;
  // The same pseudo-random deviations on every rank (Eigen's Random with one seed).
  std::srand(7);
  const Eigen::MatrixXd D = 1e-3 * Eigen::MatrixXd::Random(n, S);
  const Eigen::VectorXd w = Eigen::VectorXd::Constant(S, 1.0 / S);
  const Eigen::MatrixXd deviations = D.colwise() - D * w;  // centred, as the filter's
  std::vector<bcassim::ColumnBlock> blocks(static_cast<size_t>(size));
  for (int r = 0, first = 0; r < size; ++r) {
    const int count = S / size + (r < S % size ? 1 : 0);
    blocks[static_cast<size_t>(r)] = {first, count};
    first += count;
  }
  const bcassim::ColumnBlock mine = blocks[static_cast<size_t>(rank)];
  const Eigen::MatrixXd myForecasts = deviations.middleCols(mine.first, mine.count);
  const Eigen::VectorXd myWeights = w.segment(mine.first, mine.count);

  Eigen::MatrixXd alone, shared;
  bcassim::SharedGramWorkspace workspace;
  Eigen::VectorXd packed;
  if (rank == 0) bcassim::weightedGram(deviations, w, alone);
  double gram = 0;
  if (size == 1) {
    gram = medianSeconds([&] { bcassim::weightedGram(deviations, w, shared); });
  } else {
    gram = medianSeconds([&] {
      if (rank == 0) {
        shared.resize(n, n);
        bcassim::reduceSharedGram(deviations, w, blocks, shared, packed);
      } else {
        bcassim::contributeBlockGram(myForecasts, myWeights, 1.0, n, workspace);
      }
    });
  }
  // The reduction alone, of what travels: the lower triangle.
  const int triangle = n * (n + 1) / 2;
  Eigen::VectorXd buffer = Eigen::VectorXd::Zero(triangle);
  const double reduce = size == 1 ? 0.0 : medianSeconds([&] {
    MPI_Reduce(rank == 0 ? MPI_IN_PLACE : buffer.data(), rank == 0 ? buffer.data() : nullptr,
               triangle, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  });

  // A covariance like the filter's: the Gram matrix plus a small diagonal.
  Eigen::MatrixXd P = alone;
  if (rank == 0) P.diagonal().array() += 1e-9;
  Eigen::MatrixXd Lalone, Lshared(n, n);
  if (rank == 0) bcassim::choleskyLower(P, Lalone);
  bcassim::ScalapackCholesky scalapack(size);
  const double cholesky = medianSeconds([&] {
    if (size == 1) {
      bcassim::choleskyLower(P, Lshared);
    } else {
      scalapack.factor(n, rank == 0 ? P.data() : nullptr, rank == 0 ? Lshared.data() : nullptr);
    }
  });
  // ScaLAPACK itself, also on one rank: its pdpotrf and the moves of A and L (medians).
  std::vector<double> moves, factors, packs;
  for (int repeat = 0; repeat < 5; ++repeat) {
    Eigen::MatrixXd L(n, n);
    scalapack.factor(n, rank == 0 ? P.data() : nullptr, rank == 0 ? L.data() : nullptr);
    moves.push_back(scalapack.lastMoveSeconds());
    factors.push_back(scalapack.lastFactorSeconds());
    packs.push_back(scalapack.lastPackSeconds());
  }
  std::sort(packs.begin(), packs.end());
  std::sort(moves.begin(), moves.end());
  std::sort(factors.begin(), factors.end());
  if (rank == 0) {
    Lshared.triangularView<Eigen::StrictlyUpper>().setZero();
    std::printf(
        "dense algebra: ranks %d, n %d, S %d: gram %.2f ms, reduce %.2f ms, "
        "cholesky %.2f ms (ScaLAPACK: pdpotrf %.2f ms, moving A and L %.2f ms, of which "
        "packing %.2f ms); "
        "shared vs alone: gram %.1e, factor %.1e\n",
        size, n, S, 1e3 * gram, 1e3 * reduce, 1e3 * cholesky, 1e3 * factors[2], 1e3 * moves[2],
        1e3 * packs[2], normwiseDifference(alone, shared), normwiseDifference(Lalone, Lshared));
  }
  MPI_Finalize();
  return 0;
}
