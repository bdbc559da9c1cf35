// Run under mpirun by ctest (MpiSharedAlgebra.*): a covariance kept over the ranks
// (BlockCyclicCovariance, UkfCovarianceShare) against the same operations on one dense matrix in
// one process, for sizes that spread ScaLAPACK's 128-row blocks over every rank of a 1 x 3 (or
// 2 x 2) grid: round trips exact, the Gram matrix of unequal blocks of columns (one empty), the
// Kalman update, the Cholesky factor and its columns and suffix sums, a repaired factor equal to
// choleskyWithRepair's, a non-finite matrix refused on every rank, and each rank's block of
// simplex and star sigma points. Exit 0 when all hold; otherwise one line per failure on rank 0
// and exit 1.
#include <mpi.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/assimilation/CovarianceRepair.h"
#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/assimilation/SigmaPointSet.h"
#include "bcassim/assimilation/StarSigmaPoints.h"
#include "bcassim/distributed/BlockCyclicCovariance.h"
#include "bcassim/distributed/UkfCovarianceShare.h"

namespace {

double normwise(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / a.cwiseAbs().maxCoeff();
}

// The whole matrix on rank 0 (others: an empty one).
Eigen::MatrixXd gathered(const bcassim::BlockCyclicCovariance& P, int rank) {
  Eigen::MatrixXd out(rank == 0 ? P.size() : 0, rank == 0 ? P.size() : 0);
  P.gather(rank == 0 ? out.data() : nullptr);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int failures = 0;
  const auto check = [&](bool ok, const char* what, int n, double value) {
    if (rank == 0 && !ok) {
      std::printf("FAILED: %s (n %d): %.3g\n", what, n, value);
      ++failures;
    }
  };
  for (const int n : {300, 401}) {
    const int S = n + 1;
    std::mt19937 rng(static_cast<unsigned>(n));  // the same numbers on every rank
    std::normal_distribution<double> g(0.0, 1.0);
    Eigen::MatrixXd F(n, S);
    for (Eigen::Index i = 0; i < F.size(); ++i) F(i) = 0.3 + 1e-3 * g(rng);
    Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(S, 1.0, 3.0);
    w /= w.sum();
    const Eigen::MatrixXd deviations = 0.7 * (F.colwise() - F * w);
    Eigen::MatrixXd alone;
    bcassim::weightedGram(deviations, w, alone, 1);  // the BLAS path, whatever n

    bcassim::BlockCyclicCovariance P(size, n);
    // Round trips.
    P.scatter(rank == 0 ? alone.data() : nullptr);
    Eigen::MatrixXd back = gathered(P, rank);
    if (rank == 0) check(back == alone, "scatter and gather", n, normwise(alone, back));
    const Eigen::VectorXd diagonal = P.diagonal();
    if (rank == 0) check(diagonal == alone.diagonal(), "diagonal", n, 0);
    const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(n, 1e-9, 2e-9);
    P.addToDiagonal(q);
    back = gathered(P, rank);
    if (rank == 0) {
      Eigen::MatrixXd expected = alone;
      expected.diagonal() += q;
      check(back == expected, "diagonal added", n, 0);
    }

    // The Gram matrix: rank 0 the first 5 columns, the next ranks the rest, the last rank none
    // (with 3 ranks or more; alone or with 2, the last rank takes what is left).
    const int sharing = std::max(size - 2, 1);
    int first = 0, count = size == 1 ? S : 5;
    for (int r = 1; r <= rank; ++r) {
      first += count;
      count = r == size - 1 && size > 2 ? 0 : (S - 5) / sharing + (r == 1 ? (S - 5) % sharing : 0);
    }
    P.assignGram(deviations.middleCols(first, count), w.segment(first, count));
    back = gathered(P, rank);
    if (rank == 0) {
      const double d = normwise(alone, back);
      check(d < 1e-13, "Gram matrix over the ranks against the whole one", n, d);
    }
    // The Kalman update, undone by restore().
    const Eigen::MatrixXd gram = back;
    P.keep();
    Eigen::MatrixXd G(7, n);
    for (Eigen::Index i = 0; i < G.size(); ++i) G(i) = 1e-4 * g(rng);
    P.subtractGram(G);
    back = gathered(P, rank);
    Eigen::MatrixXd updated = alone;
    bcassim::subtractGram(G, updated, 1);
    if (rank == 0) {
      const double d = normwise(updated, back);
      check(d < 1e-13, "P -= G^T G piece by piece", n, d);
    }
    P.restore();
    back = gathered(P, rank);
    if (rank == 0) check(back == gram, "restore puts the kept matrix back", n, 0);

    // The factor, its columns and suffix sums.
    Eigen::MatrixXd spd = alone;
    spd.diagonal().array() += 1e-9;
    P.scatter(rank == 0 ? spd.data() : nullptr);
    bcassim::RepairLog log;
    P.factor(log);
    Eigen::MatrixXd L;
    if (!bcassim::choleskyLower(spd, L, 1)) check(false, "LAPACK factors the test matrix", n, 0);
    check(log.repairs == 0, "a positive definite matrix factored without repair", n, log.repairs);
    std::vector<std::vector<Eigen::Index>> needed(static_cast<size_t>(size));
    for (int r = 0; r < size; ++r)
      for (Eigen::Index j = r; j < n; j += 3 + r) needed[static_cast<size_t>(r)].push_back(j);
    Eigen::MatrixXd columns;
    P.factorColumns(needed, columns);
    double worst = 0;
    for (size_t k = 0; k < needed[static_cast<size_t>(rank)].size(); ++k)
      worst = std::max(worst, (columns.col(static_cast<Eigen::Index>(k)) -
                               L.col(needed[static_cast<size_t>(rank)][k]))
                                      .cwiseAbs()
                                      .maxCoeff() /
                                  L.cwiseAbs().maxCoeff());
    MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    check(worst < 1e-13, "the factor's columns on every rank against LAPACK's", n, worst);
    std::vector<Eigen::Index> from;
    for (int r = 0; r < size; ++r) from.push_back(r * n / size + 1);
    const Eigen::VectorXd coefficient = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
    const Eigen::VectorXd suffix = P.factorSuffixSum(from, coefficient);
    const Eigen::Index mine = from[static_cast<size_t>(rank)];
    const Eigen::VectorXd expected = L.rightCols(n - mine) * coefficient.tail(n - mine);
    double suffixError = (suffix - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff();
    MPI_Allreduce(MPI_IN_PLACE, &suffixError, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    check(suffixError < 1e-13, "the factor's suffix sums", n, suffixError);

    // A repaired factor: the same jitter as choleskyWithRepair, for a zero-variance entry (a
    // full-state UKF's fixed node: no borderline jitter that round-off could tip either way).
    Eigen::MatrixXd indefinite = spd;
    indefinite.row(n / 2).setZero();
    indefinite.col(n / 2).setZero();
    P.scatter(rank == 0 ? indefinite.data() : nullptr);
    bcassim::RepairLog repaired, repairedAlone;
    P.factor(repaired);
    const Eigen::MatrixXd Lrepaired = bcassim::choleskyWithRepair(indefinite, repairedAlone);
    // The jitter's scale, the diagonal's mean, is summed in another order: equal to round-off.
    const double jitterDifference =
        std::abs(repaired.largestJitter / repairedAlone.largestJitter - 1.0);
    check(repaired.repairs == 1 && repairedAlone.repairs == 1 && jitterDifference < 1e-12,
          "one repair with choleskyWithRepair's jitter", n, jitterDifference);
    needed.assign(static_cast<size_t>(size), {});
    for (Eigen::Index j = 0; j < n; ++j) needed[0].push_back(j);
    P.factorColumns(needed, columns);
    if (rank == 0) {
      const double d = normwise(Lrepaired, columns);
      check(d < 1e-12, "the repaired factor against choleskyWithRepair's", n, d);
    }
    Eigen::MatrixXd broken = spd;
    broken(3, 1) = std::numeric_limits<double>::quiet_NaN();
    P.scatter(rank == 0 ? broken.data() : nullptr);
    int refused = 0;
    try {
      P.factor(log);
    } catch (const bcassim::NumericalError&) {
      refused = 1;
    }
    MPI_Allreduce(MPI_IN_PLACE, &refused, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    check(refused == 1, "a non-finite covariance refused on every rank", n, 0);

    // Each rank's sigma points, simplex and star, against the whole set's.
    for (const bool simplex : {true, false}) {
      const bcassim::SigmaPointSet set =
          simplex ? bcassim::makeSigmaPoints(bcassim::SigmaPointKind::Simplex, n)
                  : bcassim::starSigmaPoints(n);
      bcassim::UkfCovarianceShare share(size, bcassim::compactColumns(set), set.weights);
      share.covariance().scatter(rank == 0 ? spd.data() : nullptr);
      const Eigen::VectorXd x = F.col(0);
      bcassim::RepairLog ignored;
      const Eigen::MatrixXd X = share.drawPoints(x, 0.3, ignored);
      const Eigen::MatrixXd whole = set.points(x, 0.3 * L);
      const bcassim::ColumnBlock b = share.block();
      double d = b.count == 0 ? 0.0
                              : (X - whole.middleCols(b.first, b.count)).cwiseAbs().maxCoeff() /
                                    (whole.colwise() - x).cwiseAbs().maxCoeff();
      MPI_Allreduce(MPI_IN_PLACE, &d, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      check(d < 1e-13,
            simplex ? "each rank's simplex sigma points" : "each rank's star sigma points", n, d);
    }
  }
  if (rank == 0 && failures == 0)
    std::printf("the covariance kept over the ranks equals the kernels alone\n");
  MPI_Finalize();
  return failures == 0 ? 0 : 1;
}
