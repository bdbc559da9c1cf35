// Run under mpirun by ctest (MpiSharedAlgebra.*): the full-state UKF's dense algebra shared by
// the ranks equals the system BLAS/LAPACK's alone on rank 0, for sizes that spread ScaLAPACK's
// 128-row blocks over every rank of a 1 x 3 (or 2 x 2) grid, with blocks of columns of unequal
// weights, an empty block, and a matrix that is not positive definite (every rank says false).
// Exit 0 when all hold; otherwise one line per failure on rank 0 and exit 1.
#include <mpi.h>

#include <Eigen/Core>
#include <cstdio>
#include <random>
#include <vector>

#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/distributed/ScalapackCholesky.h"
#include "bcassim/distributed/SharedGram.h"

namespace {

double normwise(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / a.cwiseAbs().maxCoeff();
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
  bcassim::ScalapackCholesky cholesky(size);
  for (const int n : {300, 401}) {
    // Columns: rank 0 the first 5, the next ranks the rest, the last rank none.
    const int S = n + 1;
    std::mt19937 rng(static_cast<unsigned>(n));  // the same numbers on every rank
    std::normal_distribution<double> g(0.0, 1.0);
    Eigen::MatrixXd F(n, S);
    for (Eigen::Index i = 0; i < F.size(); ++i) F(i) = 0.3 + 1e-3 * g(rng);
    Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(S, 1.0, 3.0);
    w /= w.sum();
    const double scale = 0.7;
    const Eigen::MatrixXd deviations = scale * (F.colwise() - F * w);
    std::vector<bcassim::ColumnBlock> blocks(static_cast<size_t>(size));
    blocks[0] = {0, 5};
    for (int r = 1, first = 5; r < size; ++r) {
      const int count =
          r == size - 1 ? 0 : (S - 5) / (size - 2) + (r == 1 ? (S - 5) % (size - 2) : 0);
      blocks[static_cast<size_t>(r)] = {first, count};
      first += count;
    }
    Eigen::MatrixXd alone, shared(n, n);
    bcassim::SharedGramWorkspace workspace;
    Eigen::VectorXd packed;
    bcassim::weightedGram(deviations, w, alone, 1);  // the BLAS path, whatever n
    if (rank == 0) {
      bcassim::reduceSharedGram(deviations, w, blocks, shared, packed);
    } else {
      const bcassim::ColumnBlock b = blocks[static_cast<size_t>(rank)];
      bcassim::contributeBlockGram(F.middleCols(b.first, b.count), w.segment(b.first, b.count),
                                   scale, n, workspace);
    }
    if (rank == 0) {
      const double d = normwise(alone, shared);
      check(d < 1e-13, "shared Gram matrix against the whole one", n, d);
      check(shared == shared.transpose(), "shared Gram matrix symmetric", n, 0);
    }

    Eigen::MatrixXd P = alone;
    P.diagonal().array() += 1e-9;
    Eigen::MatrixXd Lalone, L = Eigen::MatrixXd::Zero(n, n);
    bcassim::choleskyLower(P, Lalone, 1);
    const bool factored =
        cholesky.factor(n, rank == 0 ? P.data() : nullptr, rank == 0 ? L.data() : nullptr);
    check(factored, "ScaLAPACK factor of a positive definite matrix", n, 0);
    if (rank == 0) {
      L.triangularView<Eigen::StrictlyUpper>().setZero();
      const double d = normwise(Lalone, L);
      check(d < 1e-13, "ScaLAPACK factor against LAPACK's", n, d);
    }
    Eigen::MatrixXd notSpd = P;
    notSpd(n / 2, n / 2) = -1.0;
    const bool refused =
        !cholesky.factor(n, rank == 0 ? notSpd.data() : nullptr, rank == 0 ? L.data() : nullptr);
    int refusedEverywhere = refused ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &refusedEverywhere, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    check(refusedEverywhere == 1, "an indefinite matrix refused on every rank", n, 0);
  }
  if (rank == 0 && failures == 0) std::printf("shared algebra equals the kernels alone\n");
  MPI_Finalize();
  return failures == 0 ? 0 : 1;
}
