#include "bcassim/distributed/UkfCovarianceShare.h"

#include <mpi.h>

#include <limits>
#include <stdexcept>

#include "bcassim/Stopwatch.h"
#include "bcassim/assimilation/LargeDenseKernels.h"
#include "bcassim/distributed/MpiSession.h"

namespace bcassim {

Eigen::VectorXd packSigmaPoints(const SigmaPointColumns& c, const Eigen::VectorXd& weights) {
  const Eigen::Index s = c.ownCoefficient.size(), r = c.suffixCoefficient.size();
  Eigen::VectorXd out(4 + r + 3 * s);
  out(0) = static_cast<double>(c.structure);
  out(1) = static_cast<double>(c.rows);
  out(2) = static_cast<double>(s);
  out(3) = static_cast<double>(r);
  out.segment(4, r) = c.suffixCoefficient;
  out.segment(4 + r, s) = c.ownCoefficient;
  for (Eigen::Index k = 0; k < s; ++k)
    out(4 + r + s + k) = static_cast<double>(c.ownRow[static_cast<size_t>(k)]);
  out.tail(s) = weights;
  return out;
}

void unpackSigmaPoints(const Eigen::VectorXd& packed, SigmaPointColumns& c,
                       Eigen::VectorXd& weights) {
  if (packed.size() < 4) throw std::runtime_error("MPI: a sigma-point set too short to read");
  const auto s = static_cast<Eigen::Index>(packed(2)), r = static_cast<Eigen::Index>(packed(3));
  if (packed.size() != 4 + r + 3 * s)
    throw std::runtime_error("MPI: a sigma-point set of the wrong size");
  c.structure = static_cast<UnitStructure>(static_cast<int>(packed(0)));
  c.rows = static_cast<Eigen::Index>(packed(1));
  c.suffixCoefficient = packed.segment(4, r);
  c.ownCoefficient = packed.segment(4 + r, s);
  c.ownRow.resize(static_cast<size_t>(s));
  for (Eigen::Index k = 0; k < s; ++k)
    c.ownRow[static_cast<size_t>(k)] = static_cast<Eigen::Index>(packed(4 + r + s + k));
  weights = packed.tail(s);
}

UkfCovarianceShare::UkfCovarianceShare(int ranks, SigmaPointColumns columns,
                                       Eigen::VectorXd weights)
    : columns_(std::move(columns)),
      weights_(std::move(weights)),
      blocks_(equalColumnBlocks(static_cast<int>(weights_.size()), ranks)),
      P_(ranks, static_cast<int>(columns_.rows)) {
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  // The blocks are the same every step: so are the factor's columns each rank reads.
  for (const ColumnBlock& b : blocks_) {
    needed_.push_back(columns_.factorColumns(b.first, b.count));
    after_.push_back(b.first + b.count);
  }
}

Eigen::MatrixXd UkfCovarianceShare::drawPoints(const Eigen::VectorXd& x, double spread,
                                               RepairLog& repairs) {
  const Clock::time_point start = Clock::now();
  P_.factor(repairs);
  const Clock::time_point factored = Clock::now();
  Eigen::MatrixXd columns;
  P_.factorColumns(needed_, columns);
  Eigen::VectorXd suffix;
  if (columns_.structure == UnitStructure::Simplex)
    suffix = spread * P_.factorSuffixSum(after_, columns_.suffixCoefficient);
  columns *= spread;
  const Clock::time_point handed = Clock::now();
  const ColumnBlock b = block();
  Eigen::MatrixXd X = columns_.points(x, b.first, b.count, columns, suffix);
  times_.factor = secondsBetween(start, factored);
  times_.pdpotrf = P_.lastFactorSeconds();
  times_.columns = secondsBetween(factored, handed);
  times_.points = secondsSince(handed);
  return X;
}

Eigen::VectorXd UkfCovarianceShare::moments(double spread) {
  const Clock::time_point start = Clock::now();
  const ColumnBlock b = block();
  const Eigen::Index n = columns_.rows;
  // A rank without this step's forecasts (a protocol error) still joins the collectives, adding
  // NaN, so that rank 0 stops on a non-finite covariance instead of using one without them.
  if (forecasts_.rows() != n || forecasts_.cols() != b.count)
    forecasts_ = Eigen::MatrixXd::Constant(n, b.count, std::numeric_limits<double>::quiet_NaN());
  const Eigen::VectorXd w = weights_.segment(b.first, b.count);
  const Eigen::VectorXd partial = forecasts_ * w;
  Eigen::VectorXd mean(n);
  checkMpi(MPI_Reduce(partial.data(), mean.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, 0,
                      MPI_COMM_WORLD),
           "summing the forecasts' mean");
  // Rank 0's sum for every rank: the same mean everywhere, bit for bit.
  checkMpi(MPI_Bcast(mean.data(), static_cast<int>(n), MPI_DOUBLE, 0, MPI_COMM_WORLD),
           "sending the forecasts' mean");
  deviations_ = (1.0 / spread) * (forecasts_.colwise() - mean);
  P_.assignGram(deviations_, w);
  times_.gramProducts = P_.lastGramProductSeconds();
  times_.gramReduce = P_.lastGramReduceSeconds();
  times_.moments = secondsSince(start);
  return mean;
}

Eigen::MatrixXd UkfCovarianceShare::correct(const Eigen::MatrixXd* H, int m) {
  const Clock::time_point start = Clock::now();
  const ColumnBlock b = block();
  std::vector<int> counts, offsets;
  for (const ColumnBlock& c : blocks_) {
    counts.push_back(m * c.count);
    offsets.push_back(m * c.first);
  }
  Eigen::MatrixXd mine(m, b.count);
  checkMpi(MPI_Scatterv(H != nullptr ? H->data() : nullptr, counts.data(), offsets.data(),
                        MPI_DOUBLE, mine.data(), m * b.count, MPI_DOUBLE, 0, MPI_COMM_WORLD),
           "sending the correction's weights to the ranks");
  Eigen::MatrixXd partial;  // G's share H_r D_r^T
  multiplyByTranspose(mine, deviations_, partial);
  Eigen::MatrixXd G(m, columns_.rows);
  checkMpi(MPI_Reduce(partial.data(), G.data(), static_cast<int>(G.size()), MPI_DOUBLE, MPI_SUM, 0,
                      MPI_COMM_WORLD),
           "summing the Kalman gain's factor");
  checkMpi(MPI_Bcast(G.data(), static_cast<int>(G.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD),
           "sending the Kalman gain's factor");
  P_.subtractGram(G);
  times_.correct = secondsSince(start);
  return G;
}

}  // namespace bcassim
