#include "bcassim/distributed/SharedGram.h"

#include <fmt/format.h>
#include <mpi.h>

#include <limits>
#include <stdexcept>

#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/distributed/MpiSession.h"

namespace bcassim {

namespace {

void reduceToRoot(const void* send, double* receive, Eigen::Index size) {
  if (size > std::numeric_limits<int>::max())
    throw std::runtime_error(fmt::format(
        "a Gram matrix of {} entries is too large to add over MPI (over 2^31 entries)", size));
  checkMpi(
      MPI_Reduce(send, receive, static_cast<int>(size), MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD),
      "adding the ranks' Gram matrices");
}

// The lower triangle, column by column: half the bytes over the link and half the sums of a
// reduction of the whole matrix.
void packLower(const Eigen::MatrixXd& G, Eigen::VectorXd& packed) {
  const Eigen::Index n = G.rows();
  packed.resize(n * (n + 1) / 2);
  for (Eigen::Index j = 0, at = 0; j < n; at += n - j, ++j)
    packed.segment(at, n - j) = G.col(j).tail(n - j);
}

void unpackLower(const Eigen::VectorXd& packed, Eigen::MatrixXd& G) {
  const Eigen::Index n = G.rows();
  for (Eigen::Index j = 0, at = 0; j < n; at += n - j, ++j)
    G.col(j).tail(n - j) = packed.segment(at, n - j);
}

}  // namespace

void contributeBlockGram(const Eigen::MatrixXd& forecasts, const Eigen::VectorXd& w, double scale,
                         Eigen::Index rows, SharedGramWorkspace& workspace) {
  Eigen::MatrixXd& G = workspace.gram;
  if (w.size() > 0) {
    const Eigen::MatrixXd D = scale * (forecasts.colwise() - forecasts.col(0));
    weightedGramLower(D, w, G);
  } else {
    G.setZero(rows, rows);
  }
  packLower(G, workspace.packed);
  reduceToRoot(workspace.packed.data(), nullptr, workspace.packed.size());
}

void reduceSharedGram(const Eigen::MatrixXd& deviations, const Eigen::VectorXd& w,
                      const std::vector<ColumnBlock>& blocks, Eigen::MatrixXd& P,
                      Eigen::VectorXd& packed) {
  const Eigen::Index n = deviations.rows();
  const ColumnBlock own = blocks.at(0);
  // Lower triangles only until the end (the upper ones are summed, never read).
  weightedGramLower(deviations.middleCols(own.first, own.count), w.segment(own.first, own.count),
                    P);
  packLower(P, packed);
  reduceToRoot(MPI_IN_PLACE, packed.data(), packed.size());
  unpackLower(packed, P);
  // Rank r's G_r is about d = its first column: sum_j w_j d_j d_j^T = G_r + s d^T + d s^T +
  // W d d^T with s = sum_j w_j (d_j - d) and W = sum_j w_j, one product for every block.
  Eigen::MatrixXd U(n, 2 * static_cast<Eigen::Index>(blocks.size() - 1)), V(n, U.cols());
  Eigen::Index k = 0;
  for (size_t r = 1; r < blocks.size(); ++r) {
    const ColumnBlock& b = blocks[r];
    if (b.count == 0) continue;
    const Eigen::VectorXd d = deviations.col(b.first);
    const Eigen::VectorXd wb = w.segment(b.first, b.count);
    const Eigen::VectorXd s = deviations.middleCols(b.first, b.count) * wb - wb.sum() * d;
    U.middleCols(k, 2) << s, d;
    V.middleCols(k, 2) << d, s + wb.sum() * d;
    k += 2;
  }
  if (k > 0) P.triangularView<Eigen::Lower>() += U.leftCols(k) * V.leftCols(k).transpose();
  P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
}

}  // namespace bcassim
