#include "bcassim/atlas/FaceKernelSum.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "bcassim/atlas/FastExp.h"

namespace bcassim {
namespace {

constexpr Eigen::Index kBlockI = 32;  // rows of a per task; their accumulators stay in registers/L1
constexpr Eigen::Index kTileJ = 128;  // columns of b per tile: 7 arrays of 1 KB stay in L1
// Pairs farther apart than this many squared kernel widths are skipped, tile by tile: each
// weighs below exp(-50) ~ 2e-22 of a coincident pair, far below rounding of the sum.
constexpr double kCutoff = 50.0;

struct Box {
  double lo[3], hi[3];
};

// Bounding box of the centres of slots [begin, end).
Box centreBox(const OrientedFaces& f, Eigen::Index begin, Eigen::Index end) {
  Box b{{f.cx[begin], f.cy[begin], f.cz[begin]}, {f.cx[begin], f.cy[begin], f.cz[begin]}};
  for (Eigen::Index i = begin + 1; i < end; ++i) {
    const double p[3] = {f.cx[i], f.cy[i], f.cz[i]};
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], p[d]);
      b.hi[d] = std::max(b.hi[d], p[d]);
    }
  }
  return b;
}

double squaredGap(const Box& a, const Box& b) {
  double g2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double g = std::max({0.0, a.lo[d] - b.hi[d], b.lo[d] - a.hi[d]});
    g2 += g * g;
  }
  return g2;
}

using TileArray = Eigen::Array<double, kTileJ, 1>;
using ConstMap = Eigen::Map<const Eigen::ArrayXd>;

// Sums over j of one tile for row i. k_j is the pair term, t_j the factor of m_j in d/dn_i.
struct RowSums {
  double s0 = 0, sx = 0, sy = 0, sz = 0;  // sum k_j, sum k_j d_j
  double tx = 0, ty = 0, tz = 0;          // sum t_j m_j
};

template <FaceKernelKind kKind, bool kGrad>
void tileRow(const OrientedFaces& b, Eigen::Index j0, Eigen::Index nj, double s, double cix,
             double ciy, double ciz, double nix, double niy, double niz, TileArray& k, TileArray& t,
             RowSums& acc) {
  const double* bx = b.cx.data() + j0;
  const double* by = b.cy.data() + j0;
  const double* bz = b.cz.data() + j0;
  const double* mx = b.nx.data() + j0;
  const double* my = b.ny.data() + j0;
  const double* mz = b.nz.data() + j0;
  const double* im = b.invNorm.data() + j0;
  // Element-wise passes without reductions, so that the compiler vectorises them (fastExp
  // included); the clamp gets its own pass (see FastExp.h).
  for (Eigen::Index j = 0; j < nj; ++j) {
    const double dx = cix - bx[j], dy = ciy - by[j], dz = ciz - bz[j];
    const double arg = -(dx * dx + dy * dy + dz * dz) * s;
    k[j] = arg < detail::kFastExpMin ? detail::kFastExpMin : arg;
  }
  for (Eigen::Index j = 0; j < nj; ++j) {
    const double e = detail::fastExp(k[j]);
    const double dot = nix * mx[j] + niy * my[j] + niz * mz[j];
    if constexpr (kKind == FaceKernelKind::Varifold) {
      t[j] = e * dot * im[j];
      k[j] = t[j] * dot;
    } else {
      t[j] = e;
      k[j] = e * dot;
    }
  }
  // Reductions through Eigen, which vectorises them with its own packet sums.
  const auto kk = k.head(nj);
  acc.s0 += kk.sum();
  if constexpr (kGrad) {
    const auto tt = t.head(nj);
    acc.sx += (kk * ConstMap(bx, nj)).sum();
    acc.sy += (kk * ConstMap(by, nj)).sum();
    acc.sz += (kk * ConstMap(bz, nj)).sum();
    acc.tx += (tt * ConstMap(mx, nj)).sum();
    acc.ty += (tt * ConstMap(my, nj)).sum();
    acc.tz += (tt * ConstMap(mz, nj)).sum();
  }
}

template <FaceKernelKind kKind, bool kGrad>
double sum(const OrientedFaces& a, const OrientedFaces& b, double sigma, Eigen::MatrixX3d* gc,
           Eigen::MatrixX3d* gn) {
  const double s = 1.0 / (sigma * sigma);
  const Eigen::Index na = a.size(), nb = b.size();
  std::vector<double> rowValue(static_cast<size_t>(na));
  if constexpr (kGrad) {
    gc->resize(na, 3);
    gn->resize(na, 3);
  }
  const Eigen::Index tiles = (nb + kTileJ - 1) / kTileJ;
  std::vector<Box> tileBox(static_cast<size_t>(tiles));
  for (Eigen::Index tj = 0; tj < tiles; ++tj) {
    tileBox[tj] = centreBox(b, tj * kTileJ, std::min(nb, (tj + 1) * kTileJ));
  }
  const double gapLimit = kCutoff / s;
  // One task per block of kBlockI rows, so that the fixed-size accumulators always fit.
  const Eigen::Index blocks = (na + kBlockI - 1) / kBlockI;
  tbb::parallel_for(Eigen::Index(0), blocks, [&](Eigen::Index block) {
    RowSums acc[kBlockI];
    TileArray k, t;
    const Eigen::Index i0 = block * kBlockI, ni = std::min(kBlockI, na - i0);
    const Box blockBox = centreBox(a, i0, i0 + ni);
    for (Eigen::Index tj = 0; tj < tiles; ++tj) {
      if (squaredGap(blockBox, tileBox[tj]) > gapLimit) continue;
      const Eigen::Index j0 = tj * kTileJ, nj = std::min(kTileJ, nb - j0);
      for (Eigen::Index l = 0; l < ni; ++l) {
        const Eigen::Index i = i0 + l;
        tileRow<kKind, kGrad>(b, j0, nj, s, a.cx[i], a.cy[i], a.cz[i], a.nx[i], a.ny[i], a.nz[i], k,
                              t, acc[l]);
      }
    }
    for (Eigen::Index l = 0; l < ni; ++l) {
      const Eigen::Index i = i0 + l;
      const RowSums& q = acc[l];
      // The varifold's 1/|n_i| is constant over j: applied once here.
      const double w = kKind == FaceKernelKind::Varifold ? a.invNorm[i] : 1.0;
      rowValue[i] = w * q.s0;
      if constexpr (kGrad) {
        const Eigen::RowVector3d c(a.cx[i], a.cy[i], a.cz[i]), n(a.nx[i], a.ny[i], a.nz[i]);
        const Eigen::RowVector3d sd(q.sx, q.sy, q.sz), tm(q.tx, q.ty, q.tz);
        // d/dc_i exp(-|c_i - d_j|^2 s) = -2 s (c_i - d_j) exp(...).
        gc->row(i) = (-2.0 * s * w) * (q.s0 * c - sd);
        if constexpr (kKind == FaceKernelKind::Varifold) {
          // d/dn (n.m)^2 / (|n||m|) = 2 (n.m) m / (|n||m|) - (n.m)^2 n / (|n|^3 |m|).
          gn->row(i) = (2.0 * w) * tm - (w * w * w * q.s0) * n;
        } else {
          gn->row(i) = tm;
        }
      }
    }
  });
  double total = 0.0;
  for (double v : rowValue) total += v;
  return total;
}

}  // namespace

double faceKernelSum(const OrientedFaces& a, const OrientedFaces& b, double sigma,
                     FaceKernelKind kind, Eigen::MatrixX3d* gc, Eigen::MatrixX3d* gn) {
  const bool grad = gc != nullptr && gn != nullptr;
  if (kind == FaceKernelKind::Varifold) {
    return grad ? sum<FaceKernelKind::Varifold, true>(a, b, sigma, gc, gn)
                : sum<FaceKernelKind::Varifold, false>(a, b, sigma, gc, gn);
  }
  return grad ? sum<FaceKernelKind::Current, true>(a, b, sigma, gc, gn)
              : sum<FaceKernelKind::Current, false>(a, b, sigma, gc, gn);
}

}  // namespace bcassim
