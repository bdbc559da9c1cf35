// The full-state UKF's dense algebra on R ranks, for the MPI executor's cost model
// (docs/benchmarks.md §8): the step's parts that touch the n x n covariance, alone (rank 0's
// BLAS/LAPACK, as the threaded filter runs them) and kept over the ranks as `assimilate --mpi`
// keeps it (UkfCovarianceShare: the factor in place, each rank's factor columns and sigma points,
// the mean and the Gram matrix reduce-scattered into the pieces, the Kalman update piece by
// piece). Medians of 5 after one warm-up, each the slowest rank's (a barrier after each); the
// kept results are checked against the lone ones (largest entry difference over the largest).
// Usage: mpirun -np R bench_dense_algebra [n=2791] [S=n+1 simplex points] [m=45 observations]
#include <malloc.h>
#include <mpi.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/assimilation/SimplexSigmaPoints.h"
#include "bcassim/distributed/UkfCovarianceShare.h"

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

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double normwiseDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace

int main(int argc, char** argv) {
  // As bcassim's main: freed blocks kept, so that each step does not fault fresh pages in.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int n = argc > 1 ? std::atoi(argv[1]) : 2791;
  const int m = argc > 2 ? std::atoi(argv[2]) : 45;
  const bcassim::SigmaPointSet set = bcassim::simplexSigmaPoints(n);
  const int S = static_cast<int>(set.count());
  const Eigen::VectorXd& w = set.weights;
  // The same pseudo-random forecasts on every rank (Eigen's Random with one seed).
  std::srand(7);
  const Eigen::MatrixXd F = 1e-3 * Eigen::MatrixXd::Random(n, S);
  const Eigen::MatrixXd H = Eigen::MatrixXd::Random(m, S);
  const Eigen::VectorXd x = F * w;
  const Eigen::MatrixXd deviations = F.colwise() - x;

  // Alone, on rank 0 (the others wait at the barriers).
  Eigen::MatrixXd alone, Lalone, points, updated;
  const double gramAlone = medianSeconds([&] {
    if (rank == 0) bcassim::weightedGram(deviations, w, alone);
  });
  Eigen::MatrixXd P = alone;
  if (rank == 0) P.diagonal().array() += 1e-9;
  const double choleskyAlone = medianSeconds([&] {
    if (rank == 0) bcassim::choleskyLower(P, Lalone);
  });
  const double pointsAlone = medianSeconds([&] {
    if (rank == 0) points = set.points(x, Lalone);
  });
  const double updateAlone = medianSeconds([&] {
    if (rank == 0) {
      Eigen::MatrixXd G;
      bcassim::multiply(H, deviations.transpose(), G);
      updated = P;
      bcassim::subtractGram(G, updated);
    }
  });

  // Kept over the ranks.
  bcassim::UkfCovarianceShare share(size, bcassim::compactColumns(set), w);
  const bcassim::ColumnBlock mine = share.block();
  std::vector<double> factor, pdpotrf, columns, own, products, reduce;
  Eigen::MatrixXd X;
  int runs = 0;  // the parts of the runs medianSeconds keeps (not its warm-up)
  const double draw = medianSeconds([&] {
    share.covariance().scatter(rank == 0 ? P.data() : nullptr);
    MPI_Barrier(MPI_COMM_WORLD);
    bcassim::RepairLog log;
    X = share.drawPoints(x, 1.0, log);
    if (runs++ == 0) return;
    factor.push_back(share.times().factor);
    pdpotrf.push_back(share.times().pdpotrf);
    columns.push_back(share.times().columns);
    own.push_back(share.times().points);
  });
  const double pointsError =
      rank == 0 ? normwiseDifference(points.middleCols(mine.first, mine.count).colwise() - x,
                                     X.colwise() - x)
                : 0.0;
  runs = 0;
  const double moments = medianSeconds([&] {
    share.keepForecasts(F.middleCols(mine.first, mine.count));
    share.moments(1.0);
    if (runs++ == 0) return;
    products.push_back(share.times().gramProducts);
    reduce.push_back(share.times().gramReduce);
  });
  Eigen::MatrixXd kept(rank == 0 ? n : 0, rank == 0 ? n : 0);
  share.covariance().gather(rank == 0 ? kept.data() : nullptr);
  const double gramError = rank == 0 ? normwiseDifference(alone, kept) : 0.0;
  share.covariance().scatter(rank == 0 ? P.data() : nullptr);
  share.covariance().keep();
  const double correct = medianSeconds([&] {
    share.covariance().restore();
    share.correct(rank == 0 ? &H : nullptr, m);
  });
  share.covariance().gather(rank == 0 ? kept.data() : nullptr);
  const double updateError = rank == 0 ? normwiseDifference(updated, kept) : 0.0;
  // The reduce-scatter alone, every rank ready (inside moments() it also waits for the slowest
  // rank's products): what each link moves and sums. Pieces sized as the covariance's, about
  // the packed lower triangle split evenly.
  const long long half = static_cast<long long>(n) * (n + 1) / 2;
  std::vector<int> counts(static_cast<size_t>(size));
  for (int r = 0; r < size; ++r) counts[static_cast<size_t>(r)] = static_cast<int>(half / size);
  Eigen::VectorXd whole = Eigen::VectorXd::Ones(half / size * size), piece(half / size);
  const double reduceAlone = medianSeconds([&] {
    MPI_Reduce_scatter(whole.data(), piece.data(), counts.data(), MPI_DOUBLE, MPI_SUM,
                       MPI_COMM_WORLD);
  });
  if (rank == 0)
    std::printf(
        "dense algebra: ranks %d, n %d, S %d, m %d: alone (rank 0) gram %.2f ms, cholesky %.2f ms, "
        "sigma points %.2f ms, update %.2f ms; kept over the ranks: draw %.2f ms (factor %.2f, "
        "pdpotrf %.2f, factor's columns %.2f, own points %.2f), mean and gram %.2f ms (products "
        "%.2f, reduce-scatter %.2f), correction %.2f ms; reduce-scatter alone %.2f ms; kept vs "
        "alone: gram %.1e, points %.1e, update %.1e\n",
        size, n, S, m, 1e3 * gramAlone, 1e3 * choleskyAlone, 1e3 * pointsAlone, 1e3 * updateAlone,
        1e3 * draw, 1e3 * median(factor), 1e3 * median(pdpotrf), 1e3 * median(columns),
        1e3 * median(own), 1e3 * moments, 1e3 * median(products), 1e3 * median(reduce),
        1e3 * correct, 1e3 * reduceAlone, gramError, pointsError, updateError);
  MPI_Finalize();
  return 0;
}
