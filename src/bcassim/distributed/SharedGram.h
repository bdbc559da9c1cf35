// A step's Gram matrix sum_i w_i d_i d_i^T summed over the ranks that hold the forecasts: each
// worker rank forms its own block's about its first column and MPI_Reduce adds them on rank 0,
// which moves every block to the common mean (the parallel-axis terms of Chan et al.), so the
// n^2 x columns flops are shared and only n x n matrices travel.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace bcassim {

// A worker's buffers, kept between steps (no fresh n x n allocation each step).
struct SharedGramWorkspace {
  Eigen::MatrixXd gram;
  Eigen::VectorXd packed;  // its lower triangle, as it travels
};

// A rank's columns of the step's forecasts.
struct ColumnBlock {
  int first = 0, count = 0;
};

// On a worker rank (collective with reduceSharedGram): G = scale^2 sum_j w_j (f_j - f_0)
// (f_j - f_0)^T over the columns f_j of `forecasts` (rows x w.size(); none: G = 0 of `rows`),
// added into rank 0's (its lower triangle, packed).
void contributeBlockGram(const Eigen::MatrixXd& forecasts, const Eigen::VectorXd& w, double scale,
                         Eigen::Index rows, SharedGramWorkspace& workspace);

// On rank 0 (collective with contributeBlockGram on every other rank): P = sum_i w_i d_i d_i^T
// over all columns of `deviations` (d_i = scale (f_i - mean)), with blocks[0] its own columns
// and blocks[r] those rank r holds. Rank 0 reads the other blocks' columns only for their sum and
// first column (the shift of their Gram to the mean). `packed`: a buffer kept between steps.
void reduceSharedGram(const Eigen::MatrixXd& deviations, const Eigen::VectorXd& w,
                      const std::vector<ColumnBlock>& blocks, Eigen::MatrixXd& P,
                      Eigen::VectorXd& packed);

}  // namespace bcassim
