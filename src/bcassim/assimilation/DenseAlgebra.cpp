#include "bcassim/assimilation/DenseAlgebra.h"

#include "bcassim/assimilation/LargeDenseKernels.h"

namespace bcassim {

void DenseAlgebra::weightedGram(const Eigen::MatrixXd& deviations, const Eigen::VectorXd& w,
                                double /*scale*/, Eigen::MatrixXd& P) {
  bcassim::weightedGram(deviations, w, P);
}

bool DenseAlgebra::choleskyLower(const Eigen::MatrixXd& A, Eigen::MatrixXd& L) {
  return bcassim::choleskyLower(A, L);
}

}  // namespace bcassim
