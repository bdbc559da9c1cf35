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
#include "bcassim/atlas/KernelSimd.h"

// Vector-extension values only cross always-inlined helpers: the ABI note does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace bcassim {
namespace {
// Rows per parallel task and columns per tile (the tile's kernel values stay in L1).
constexpr Eigen::Index kGaussBlockI = 16;
constexpr Eigen::Index kGaussTileJ = 256;

using Tile = std::array<double, kGaussTileJ>;
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
  tbb::parallel_for(Eigen::Index(0), (n + kGaussBlockI - 1) / kGaussBlockI, [&](Eigen::Index b) {
    const Eigen::Index end = std::min(n, (b + 1) * kGaussBlockI);
    for (Eigen::Index i = b * kGaussBlockI; i < end; ++i) body(i);
  });
}

// Columns of a #n by 3 matrix copied into arrays padded to a multiple of the widest vector (8),
// padding filled with `pad` (far positions, or zero weights, so padded terms vanish).
struct Padded3 {
  Eigen::Index n = 0, padded = 0;
  std::vector<double> c[3];
  Padded3(const Eigen::MatrixX3d& m, double pad) : n(m.rows()), padded((m.rows() + 7) / 8 * 8) {
    for (int d = 0; d < 3; ++d) {
      c[d].assign(static_cast<size_t>(padded), pad);
      for (Eigen::Index i = 0; i < n; ++i) c[d][i] = m(i, d);
    }
  }
};
constexpr double kFar = 1e150;

struct ConvolveCtx {
  const Eigen::MatrixX3d* x;
  const Padded3* y;
  const Padded3* w;
  double s;
  Eigen::MatrixX3d* v;
};

template <int W>
__attribute__((always_inline)) inline void convolveBody(const ConvolveCtx& c, Eigen::Index b) {
  using V = simd::Vd<W>;
  const Eigen::Index end = std::min(c.x->rows(), (b + 1) * kGaussBlockI);
  const double *y0 = c.y->c[0].data(), *y1 = c.y->c[1].data(), *y2 = c.y->c[2].data();
  const double *w0 = c.w->c[0].data(), *w1 = c.w->c[1].data(), *w2 = c.w->c[2].data();
  for (Eigen::Index i = b * kGaussBlockI; i < end; ++i) {
    const double p0 = (*c.x)(i, 0), p1 = (*c.x)(i, 1), p2 = (*c.x)(i, 2);
    V a0{}, a1{}, a2{};
    for (Eigen::Index j = 0; j < c.y->padded; j += W) {
      const V d0 = p0 - simd::load<W>(y0 + j), d1 = p1 - simd::load<W>(y1 + j),
              d2 = p2 - simd::load<W>(y2 + j);
      const V k = simd::gauss<W>(d0 * d0 + d1 * d1 + d2 * d2, c.s);
      a0 += k * simd::load<W>(w0 + j);
      a1 += k * simd::load<W>(w1 + j);
      a2 += k * simd::load<W>(w2 + j);
    }
    (*c.v)(i, 0) = simd::hsum<W>(a0);
    (*c.v)(i, 1) = simd::hsum<W>(a1);
    (*c.v)(i, 2) = simd::hsum<W>(a2);
  }
}
BCASSIM_SIMD_DISPATCH(convolveBlock, convolveBody, (const ConvolveCtx& c, Eigen::Index b), (c, b))

struct VjpCtx {
  const Eigen::MatrixX3d* x;
  const Eigen::MatrixX3d* eta;
  const Padded3* y;
  const Padded3* w;
  double s;
  Eigen::MatrixX3d* gx;  // #x by 3, written row by row
};

// Rows of block b; scatter (when non-null) receives dL/dy (3 padded columns) then dL/dw (3).
template <int W>
__attribute__((always_inline)) inline void vjpBody(const VjpCtx& c, Eigen::Index b,
                                                   double* scatter) {
  using V = simd::Vd<W>;
  const Eigen::Index end = std::min(c.x->rows(), (b + 1) * kGaussBlockI);
  const Eigen::Index np = c.y->padded;
  const double *y0 = c.y->c[0].data(), *y1 = c.y->c[1].data(), *y2 = c.y->c[2].data();
  const double *w0 = c.w->c[0].data(), *w1 = c.w->c[1].data(), *w2 = c.w->c[2].data();
  const double twoS = 2.0 * c.s;
  for (Eigen::Index i = b * kGaussBlockI; i < end; ++i) {
    const double p0 = (*c.x)(i, 0), p1 = (*c.x)(i, 1), p2 = (*c.x)(i, 2);
    const double e0 = (*c.eta)(i, 0), e1 = (*c.eta)(i, 1), e2 = (*c.eta)(i, 2);
    V sc{}, sy0{}, sy1{}, sy2{};
    for (Eigen::Index j = 0; j < np; j += W) {
      const V q0 = simd::load<W>(y0 + j), q1 = simd::load<W>(y1 + j), q2 = simd::load<W>(y2 + j);
      const V d0 = p0 - q0, d1 = p1 - q1, d2 = p2 - q2;
      const V k = simd::gauss<W>(d0 * d0 + d1 * d1 + d2 * d2, c.s);
      const V cc = k * (e0 * simd::load<W>(w0 + j) + e1 * simd::load<W>(w1 + j) +
                        e2 * simd::load<W>(w2 + j));
      sc += cc;
      sy0 += cc * q0;
      sy1 += cc * q1;
      sy2 += cc * q2;
      if (scatter) {
        const V tc = twoS * cc;
        double* g = scatter + j;
        simd::store<W>(g, simd::load<W>(g) + tc * d0);
        simd::store<W>(g + np, simd::load<W>(g + np) + tc * d1);
        simd::store<W>(g + 2 * np, simd::load<W>(g + 2 * np) + tc * d2);
        simd::store<W>(g + 3 * np, simd::load<W>(g + 3 * np) + k * e0);
        simd::store<W>(g + 4 * np, simd::load<W>(g + 4 * np) + k * e1);
        simd::store<W>(g + 5 * np, simd::load<W>(g + 5 * np) + k * e2);
      }
    }
    const double sumC = simd::hsum<W>(sc);
    (*c.gx)(i, 0) = -twoS * (p0 * sumC - simd::hsum<W>(sy0));
    (*c.gx)(i, 1) = -twoS * (p1 * sumC - simd::hsum<W>(sy1));
    (*c.gx)(i, 2) = -twoS * (p2 * sumC - simd::hsum<W>(sy2));
  }
}
BCASSIM_SIMD_DISPATCH(vjpBlock, vjpBody, (const VjpCtx& c, Eigen::Index b, double* scatter),
                      (c, b, scatter))

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
  const Padded3 yp(y, kFar), wp(w, 0.0);
  const ConvolveCtx ctx{&x, &yp, &wp, invSigma2_, &v};
  tbb::parallel_for(Eigen::Index(0), (x.rows() + kGaussBlockI - 1) / kGaussBlockI,
                    [&](Eigen::Index b) { convolveBlock(ctx, b); });
  return v;
}

void GaussianKernel::convolveVjp(const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                                 const Eigen::MatrixX3d& w, const Eigen::MatrixX3d& eta,
                                 Eigen::MatrixX3d* gx, Eigen::MatrixX3d* gy,
                                 Eigen::MatrixX3d* gw) const {
  // With c_ij = K_ij (eta_i . w_j): dL/dx_i = -2s sum_j c_ij (x_i - y_j),
  // dL/dy_j = +2s sum_i c_ij (x_i - y_j), dL/dw_j = sum_i K_ij eta_i. The last two are scattered
  // into per-thread padded column accumulators, summed at the end.
  const Padded3 yp(y, kFar), wp(w, 0.0);
  const Eigen::Index np = yp.padded, ny = y.rows();
  const bool scatter = gy != nullptr || gw != nullptr;
  tbb::enumerable_thread_specific<std::vector<double>> local(
      std::vector<double>(scatter ? static_cast<size_t>(6 * np) : 0, 0.0));
  Eigen::MatrixX3d gxLocal(x.rows(), 3);
  const VjpCtx ctx{&x, &eta, &yp, &wp, invSigma2_, &gxLocal};
  tbb::parallel_for(
      Eigen::Index(0), (x.rows() + kGaussBlockI - 1) / kGaussBlockI,
      [&](Eigen::Index b) { vjpBlock(ctx, b, scatter ? local.local().data() : nullptr); });
  if (gx) *gx += gxLocal;
  if (scatter) {
    for (const std::vector<double>& m : local) {
      for (int d = 0; d < 3; ++d) {
        for (Eigen::Index j = 0; j < ny; ++j) {
          if (gy) (*gy)(j, d) += m[d * np + j];
          if (gw) (*gw)(j, d) += m[(3 + d) * np + j];
        }
      }
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
    for (Eigen::Index j0 = 0; j0 < n; j0 += kGaussTileJ) {
      const Eigen::Index nj = std::min(kGaussTileJ, n - j0);
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
    for (Eigen::Index j0 = 0; j0 < n; j0 += kGaussTileJ) {
      const Eigen::Index nj = std::min(kGaussTileJ, n - j0);
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
