#include "bcassim/atlas/GaussianKernel.h"

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/atlas/FastExp.h"

namespace bcassim {
namespace {
// Rows per parallel task and columns per tile (the tile's kernel values stay in L1).
constexpr Eigen::Index kBlockI = 16;
constexpr Eigen::Index kTileJ = 256;

using Tile = std::array<double, kTileJ>;
using Col = Eigen::Map<const Eigen::ArrayXd>;

// Columns of a #n by 3 matrix as contiguous arrays (the matrix is column-major already, so these
// are views, not copies).
struct Columns {
  const double* c[3];
  explicit Columns(const Eigen::MatrixX3d& m)
      : c{m.col(0).data(), m.col(1).data(), m.col(2).data()} {}
  Col tile(int d, Eigen::Index j0, Eigen::Index nj) const { return Col(c[d] + j0, nj); }
};

// k[j] = exp(-|p - y_{j0+j}|^2 s) for j < nj, in two element-wise passes so that both vectorise
// (see FastExp.h).
inline void kernelTile(const double p[3], const Columns& y, Eigen::Index j0, Eigen::Index nj,
                       double s, Tile& k) {
  const double* y0 = y.c[0] + j0;
  const double* y1 = y.c[1] + j0;
  const double* y2 = y.c[2] + j0;
  for (Eigen::Index j = 0; j < nj; ++j) {
    const double d0 = p[0] - y0[j], d1 = p[1] - y1[j], d2 = p[2] - y2[j];
    const double arg = -(d0 * d0 + d1 * d1 + d2 * d2) * s;
    k[j] = arg < detail::kFastExpMin ? detail::kFastExpMin : arg;
  }
  for (Eigen::Index j = 0; j < nj; ++j) k[j] = detail::fastExp(k[j]);
}

inline Eigen::Map<const Eigen::ArrayXd> view(const Tile& t, Eigen::Index nj) {
  return {t.data(), nj};
}

// Runs body(i) for every row, one task per block of rows.
template <class Body>
void forEachRow(Eigen::Index n, Body&& body) {
  tbb::parallel_for(Eigen::Index(0), (n + kBlockI - 1) / kBlockI, [&](Eigen::Index b) {
    const Eigen::Index end = std::min(n, (b + 1) * kBlockI);
    for (Eigen::Index i = b * kBlockI; i < end; ++i) body(i);
  });
}
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
  const Columns yc(y), wc(w);
  const double s = invSigma2_;
  const Eigen::Index ny = y.rows();
  forEachRow(x.rows(), [&](Eigen::Index i) {
    const double p[3] = {x(i, 0), x(i, 1), x(i, 2)};
    double acc[3] = {0.0, 0.0, 0.0};
    Tile k;
    for (Eigen::Index j0 = 0; j0 < ny; j0 += kTileJ) {
      const Eigen::Index nj = std::min(kTileJ, ny - j0);
      kernelTile(p, yc, j0, nj, s, k);
      const auto kk = view(k, nj);
      for (int d = 0; d < 3; ++d) acc[d] += (kk * wc.tile(d, j0, nj)).sum();
    }
    for (int d = 0; d < 3; ++d) v(i, d) = acc[d];
  });
  return v;
}

void GaussianKernel::convolveVjp(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                                 const Eigen::MatrixX3d& w, const Eigen::MatrixX3d& eta,
                                 Eigen::MatrixX3d* gx, Eigen::MatrixX3d* gy,
                                 Eigen::MatrixX3d* gw) const {
  // With c_ij = K_ij (eta_i . w_j): dL/dx_i = -2s sum_j c_ij (x_i - y_j),
  // dL/dy_j = +2s sum_i c_ij (x_i - y_j), dL/dw_j = sum_i K_ij eta_i. The last two are scattered
  // into per-thread column accumulators (element-wise, so they vectorise), summed at the end.
  const Columns yc(y), wc(w);
  const double s = invSigma2_;
  const Eigen::Index ny = y.rows();
  const bool scatter = gy != nullptr || gw != nullptr;
  tbb::enumerable_thread_specific<Eigen::MatrixXd> local(
      Eigen::MatrixXd::Zero(scatter ? ny : 0, 6));  // columns: dL/dy (3), dL/dw (3)
  Eigen::MatrixX3d gxLocal = Eigen::MatrixX3d::Zero(x.rows(), 3);
  forEachRow(x.rows(), [&](Eigen::Index i) {
    const double p[3] = {x(i, 0), x(i, 1), x(i, 2)};
    const double e[3] = {eta(i, 0), eta(i, 1), eta(i, 2)};
    Eigen::MatrixXd* acc = scatter ? &local.local() : nullptr;
    double sumC = 0.0, sumCy[3] = {0.0, 0.0, 0.0};
    Tile k, c;
    for (Eigen::Index j0 = 0; j0 < ny; j0 += kTileJ) {
      const Eigen::Index nj = std::min(kTileJ, ny - j0);
      kernelTile(p, yc, j0, nj, s, k);
      const double* w0 = wc.c[0] + j0;
      const double* w1 = wc.c[1] + j0;
      const double* w2 = wc.c[2] + j0;
      for (Eigen::Index j = 0; j < nj; ++j)
        c[j] = k[j] * (e[0] * w0[j] + e[1] * w1[j] + e[2] * w2[j]);
      const auto cc = view(c, nj);
      sumC += cc.sum();
      for (int d = 0; d < 3; ++d) sumCy[d] += (cc * yc.tile(d, j0, nj)).sum();
      if (acc) {
        for (int d = 0; d < 3; ++d) {
          double* gyd = acc->col(d).data() + j0;
          double* gwd = acc->col(3 + d).data() + j0;
          const double* yd = yc.c[d] + j0;
          const double pd = p[d], ed = e[d], twoS = 2.0 * s;
          for (Eigen::Index j = 0; j < nj; ++j) {
            gyd[j] += twoS * c[j] * (pd - yd[j]);
            gwd[j] += k[j] * ed;
          }
        }
      }
    }
    for (int d = 0; d < 3; ++d) gxLocal(i, d) = -2.0 * s * (p[d] * sumC - sumCy[d]);
  });
  if (gx) *gx += gxLocal;
  if (scatter) {
    for (const Eigen::MatrixXd& m : local) {
      if (gy) *gy += m.leftCols(3);
      if (gw) *gw += m.rightCols(3);
    }
  }
}

double GaussianKernel::hamiltonian(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a) const {
  return 0.5 * (a.array() * convolve(q, q, a).array()).sum();
}

Eigen::MatrixX3d GaussianKernel::hamiltonianGradient(const Eigen::MatrixX3d& q,
                                                     const Eigen::MatrixX3d& a) const {
  // dH/dq_i = -2s sum_j c_ij (q_i - q_j) with c_ij = K_ij (a_i . a_j): both occurrences of q_i
  // in the double sum give the same term, cancelling the 1/2.
  Eigen::MatrixX3d g(q.rows(), 3);
  const Columns qc(q), ac(a);
  const double s = invSigma2_;
  const Eigen::Index n = q.rows();
  forEachRow(n, [&](Eigen::Index i) {
    const double p[3] = {q(i, 0), q(i, 1), q(i, 2)};
    const double ai[3] = {a(i, 0), a(i, 1), a(i, 2)};
    double sumC = 0.0, sumCq[3] = {0.0, 0.0, 0.0};
    Tile k;
    for (Eigen::Index j0 = 0; j0 < n; j0 += kTileJ) {
      const Eigen::Index nj = std::min(kTileJ, n - j0);
      kernelTile(p, qc, j0, nj, s, k);
      const double* a0 = ac.c[0] + j0;
      const double* a1 = ac.c[1] + j0;
      const double* a2 = ac.c[2] + j0;
      for (Eigen::Index j = 0; j < nj; ++j) k[j] *= ai[0] * a0[j] + ai[1] * a1[j] + ai[2] * a2[j];
      const auto cc = view(k, nj);
      sumC += cc.sum();
      for (int d = 0; d < 3; ++d) sumCq[d] += (cc * qc.tile(d, j0, nj)).sum();
    }
    for (int d = 0; d < 3; ++d) g(i, d) = -2.0 * s * (p[d] * sumC - sumCq[d]);
  });
  return g;
}

void GaussianKernel::hamiltonianGradientVjp(const Eigen::MatrixX3d& q, const Eigen::MatrixX3d& a,
                                            const Eigen::MatrixX3d& xi, Eigen::MatrixX3d* gq,
                                            Eigen::MatrixX3d* ga) const {
  // L = -2s sum_ij K_ij (a_i.a_j) xi_i.d_ij with d_ij = q_i - q_j. Symmetrising over (i, j)
  // leaves only dxi_ij = xi_i - xi_j, so each row is a plain sum over j (no scatter):
  //   dL/dq_i = -2s sum_j K_ij (a_i.a_j) [dxi_ij - 2s (dxi_ij.d_ij) d_ij],
  //   dL/da_i = -2s sum_j K_ij (dxi_ij.d_ij) a_j.
  // With c1 = K (a_i.a_j), c2 = c1 (dxi.d), c3 = K (dxi.d), the sums over j expand into
  // reductions against the columns of q, xi and a.
  const Columns qc(q), ac(a), xc(xi);
  const double s = invSigma2_;
  const Eigen::Index n = q.rows();
  forEachRow(n, [&](Eigen::Index i) {
    const double p[3] = {q(i, 0), q(i, 1), q(i, 2)};
    const double ai[3] = {a(i, 0), a(i, 1), a(i, 2)};
    const double xii[3] = {xi(i, 0), xi(i, 1), xi(i, 2)};
    double s1 = 0.0, s1x[3] = {0, 0, 0}, s2 = 0.0, s2q[3] = {0, 0, 0}, s3a[3] = {0, 0, 0};
    Tile k, c1, c2;
    for (Eigen::Index j0 = 0; j0 < n; j0 += kTileJ) {
      const Eigen::Index nj = std::min(kTileJ, n - j0);
      kernelTile(p, qc, j0, nj, s, k);
      const double *q0 = qc.c[0] + j0, *q1 = qc.c[1] + j0, *q2 = qc.c[2] + j0;
      const double *a0 = ac.c[0] + j0, *a1 = ac.c[1] + j0, *a2 = ac.c[2] + j0;
      const double *x0 = xc.c[0] + j0, *x1 = xc.c[1] + j0, *x2 = xc.c[2] + j0;
      for (Eigen::Index j = 0; j < nj; ++j) {
        const double dxd = (xii[0] - x0[j]) * (p[0] - q0[j]) + (xii[1] - x1[j]) * (p[1] - q1[j]) +
                           (xii[2] - x2[j]) * (p[2] - q2[j]);
        c1[j] = k[j] * (ai[0] * a0[j] + ai[1] * a1[j] + ai[2] * a2[j]);
        c2[j] = c1[j] * dxd;
        k[j] *= dxd;  // c3
      }
      const auto v1 = view(c1, nj), v2 = view(c2, nj), v3 = view(k, nj);
      s1 += v1.sum();
      s2 += v2.sum();
      for (int d = 0; d < 3; ++d) {
        s1x[d] += (v1 * xc.tile(d, j0, nj)).sum();
        s2q[d] += (v2 * qc.tile(d, j0, nj)).sum();
        s3a[d] += (v3 * ac.tile(d, j0, nj)).sum();
      }
    }
    for (int d = 0; d < 3; ++d) {
      const double dq = (xii[d] * s1 - s1x[d]) - 2.0 * s * (p[d] * s2 - s2q[d]);
      if (gq) (*gq)(i, d) -= 2.0 * s * dq;
      if (ga) (*ga)(i, d) -= 2.0 * s * s3a[d];
    }
  });
}

}  // namespace bcassim
