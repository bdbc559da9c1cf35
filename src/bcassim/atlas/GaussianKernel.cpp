#include "bcassim/atlas/GaussianKernel.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/atlas/FastExp.h"

namespace bcassim {
namespace {
// Rows per parallel task: control-point sets are small (hundreds), meshes a few thousand points.
constexpr Eigen::Index kGrain = 32;

// exp(-y) for y >= 0.
inline double expOfNegative(double y) { return detail::fastExp(std::max(-y, detail::kFastExpMin)); }

// Per-thread accumulator of a #rows by 3 derivative that parallel tasks over the other index
// scatter into; summed once at the end.
struct ScatterBuffer {
  tbb::enumerable_thread_specific<Eigen::MatrixX3d> local;
  explicit ScatterBuffer(Eigen::Index rows) : local(Eigen::MatrixX3d::Zero(rows, 3)) {}
  void addTo(Eigen::MatrixX3d* out) {
    for (const Eigen::MatrixX3d& m : local) *out += m;
  }
};
}  // namespace

GaussianKernel::GaussianKernel(double sigma) : sigma_(sigma), invSigma2_(1.0 / (sigma * sigma)) {
  if (!(sigma > 0.0) || !std::isfinite(sigma)) {
    throw InputError(fmt::format("Gaussian kernel width must be positive, got {}", sigma));
  }
}

double GaussianKernel::operator()(const Eigen::Vector3d& x, const Eigen::Vector3d& y) const {
  return std::exp(-(x - y).squaredNorm() * invSigma2_);
}

Eigen::MatrixX3d GaussianKernel::convolve(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                                          const Eigen::MatrixX3d& w) const {
  Eigen::MatrixX3d v(x.rows(), 3);
  const double s = invSigma2_;
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, x.rows(), kGrain), [&](const auto& r) {
    for (Eigen::Index i = r.begin(); i < r.end(); ++i) {
      const double xi0 = x(i, 0), xi1 = x(i, 1), xi2 = x(i, 2);
      double v0 = 0.0, v1 = 0.0, v2 = 0.0;
      for (Eigen::Index j = 0; j < y.rows(); ++j) {
        const double d0 = xi0 - y(j, 0), d1 = xi1 - y(j, 1), d2 = xi2 - y(j, 2);
        const double k = expOfNegative((d0 * d0 + d1 * d1 + d2 * d2) * s);
        v0 += k * w(j, 0);
        v1 += k * w(j, 1);
        v2 += k * w(j, 2);
      }
      v(i, 0) = v0;
      v(i, 1) = v1;
      v(i, 2) = v2;
    }
  });
  return v;
}

void GaussianKernel::convolveVjp(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                                 const Eigen::MatrixX3d& w, const Eigen::MatrixX3d& eta,
                                 Eigen::MatrixX3d* gx, Eigen::MatrixX3d* gy,
                                 Eigen::MatrixX3d* gw) const {
  const double s = invSigma2_;
  ScatterBuffer bufY(y.rows()), bufW(y.rows());
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, x.rows(), kGrain), [&](const auto& r) {
    Eigen::MatrixX3d& ly = bufY.local.local();
    Eigen::MatrixX3d& lw = bufW.local.local();
    for (Eigen::Index i = r.begin(); i < r.end(); ++i) {
      const Eigen::RowVector3d xi = x.row(i), ei = eta.row(i);
      Eigen::RowVector3d accX = Eigen::RowVector3d::Zero();
      for (Eigen::Index j = 0; j < y.rows(); ++j) {
        const Eigen::RowVector3d d = xi - y.row(j);
        const double k = expOfNegative(d.squaredNorm() * s);
        // d/dx_i of K(x_i, y_j) (eta_i . w_j) is K (eta_i . w_j) (-2/sigma^2) d.
        const Eigen::RowVector3d gd = (-2.0 * s * k * ei.dot(w.row(j))) * d;
        accX += gd;
        if (gy) ly.row(j) -= gd;
        if (gw) lw.row(j) += k * ei;
      }
      if (gx) gx->row(i) += accX;
    }
  });
  if (gy) bufY.addTo(gy);
  if (gw) bufW.addTo(gw);
}

double GaussianKernel::hamiltonian(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a) const {
  return 0.5 * (a.array() * convolve(q, q, a).array()).sum();
}

Eigen::MatrixX3d GaussianKernel::hamiltonianGradient(const Eigen::MatrixX3d& q,
                                                     const Eigen::MatrixX3d& a) const {
  Eigen::MatrixX3d g(q.rows(), 3);
  const double s = invSigma2_;
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, q.rows(), kGrain), [&](const auto& r) {
    for (Eigen::Index i = r.begin(); i < r.end(); ++i) {
      Eigen::RowVector3d acc = Eigen::RowVector3d::Zero();
      for (Eigen::Index j = 0; j < q.rows(); ++j) {
        const Eigen::RowVector3d d = q.row(i) - q.row(j);
        const double k = expOfNegative(d.squaredNorm() * s);
        acc += (k * a.row(i).dot(a.row(j))) * d;
      }
      // Both occurrences of q_i in the double sum give the same term, cancelling the 1/2.
      g.row(i) = (-2.0 * s) * acc;
    }
  });
  return g;
}

void GaussianKernel::hamiltonianGradientVjp(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a,
                                            const Eigen::MatrixX3d& xi, Eigen::MatrixX3d* gq,
                                            Eigen::MatrixX3d* ga) const {
  // L = -(2/s^2) sum_ij K_ij (a_i.a_j) xi_i.d_ij with d_ij = q_i - q_j; symmetrising over (i, j)
  // leaves only xi_i - xi_j, so each row is a plain sum over j (no scatter).
  const double s = invSigma2_;
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, q.rows(), kGrain), [&](const auto& r) {
    for (Eigen::Index i = r.begin(); i < r.end(); ++i) {
      Eigen::RowVector3d accQ = Eigen::RowVector3d::Zero(), accA = Eigen::RowVector3d::Zero();
      for (Eigen::Index j = 0; j < q.rows(); ++j) {
        const Eigen::RowVector3d d = q.row(i) - q.row(j);
        const Eigen::RowVector3d dxi = xi.row(i) - xi.row(j);
        const double k = expOfNegative(d.squaredNorm() * s);
        const double dxiDotD = dxi.dot(d);
        accQ += (k * a.row(i).dot(a.row(j))) * (dxi - (2.0 * s * dxiDotD) * d);
        accA += (k * dxiDotD) * a.row(j);
      }
      if (gq) gq->row(i) -= (2.0 * s) * accQ;
      if (ga) ga->row(i) -= (2.0 * s) * accA;
    }
  });
}

}  // namespace bcassim
