#include "bcassim/atlas/FaceKernelSum.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "bcassim/atlas/FastExp.h"
#include "bcassim/atlas/KernelSimd.h"

// Vector-extension values only cross always-inlined helpers: the ABI note does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace bcassim {
namespace {

constexpr Eigen::Index kBlockI =
    8;  // rows of a per task: small boxes, so that far tiles are skipped
constexpr Eigen::Index kTileJ = 16;  // columns of b per tile (a multiple of every vector width)
// Pairs farther apart than this many squared kernel widths are skipped, tile by tile: each
// weighs below exp(-50) ~ 2e-22 of a coincident pair, far below rounding of the sum.
constexpr double kCutoff = 50.0;

struct Box {
  double lo[3], hi[3];
};

// Bounding box of the centres of slots [begin, end).
Box centreBox(const double* cx, const double* cy, const double* cz, Eigen::Index begin,
              Eigen::Index end) {
  Box b{{cx[begin], cy[begin], cz[begin]}, {cx[begin], cy[begin], cz[begin]}};
  for (Eigen::Index i = begin + 1; i < end; ++i) {
    const double p[3] = {cx[i], cy[i], cz[i]};
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

// b as structure of arrays padded to whole tiles: padding slots have zero normals (so their
// terms are exactly zero) and centres far away (so that the exponent clamps).
struct PaddedFaces {
  Eigen::Index n = 0, padded = 0;
  std::vector<double> cx, cy, cz, nx, ny, nz, im;
  explicit PaddedFaces(const OrientedFaces& b) : n(b.size()) {
    padded = (n + kTileJ - 1) / kTileJ * kTileJ;
    auto fill = [&](std::vector<double>& dst, const std::vector<double>& src, double pad) {
      dst.assign(static_cast<size_t>(padded), pad);
      std::copy(src.begin(), src.end(), dst.begin());
    };
    fill(cx, b.cx, 1e150);
    fill(cy, b.cy, 1e150);
    fill(cz, b.cz, 1e150);
    fill(nx, b.nx, 0.0);
    fill(ny, b.ny, 0.0);
    fill(nz, b.nz, 0.0);
    fill(im, b.invNorm, 0.0);
  }
};

// Row sums over j for one row i, kept as W-wide vectors until the row is complete.
// k_j is the pair term, t_j the factor of m_j in d/dn_i.
template <int W>
struct RowAcc {
  simd::Vd<W> s0, sx, sy, sz;  // sum k_j, sum k_j d_j
  simd::Vd<W> tx, ty, tz;      // sum t_j m_j
};

struct SumContext {
  const OrientedFaces* a;
  const PaddedFaces* b;
  double s;
  const std::vector<Box>* tileBox;
  double gapLimit;
  double* rowValue;
  Eigen::MatrixX3d* gc;
  Eigen::MatrixX3d* gn;
};

// One block of kBlockI rows of a against every tile of b near it.
template <int W, FaceKernelKind kKind, bool kGrad>
__attribute__((always_inline)) inline void blockBody(const SumContext& ctx, Eigen::Index block) {
  const OrientedFaces& a = *ctx.a;
  const PaddedFaces& b = *ctx.b;
  const double s = ctx.s;
  const Eigen::Index na = a.size();
  const Eigen::Index i0 = block * kBlockI, ni = std::min(kBlockI, na - i0);
  RowAcc<W> acc[kBlockI];
  for (Eigen::Index l = 0; l < ni; ++l) acc[l] = RowAcc<W>{};
  const Box blockBox = centreBox(a.cx.data(), a.cy.data(), a.cz.data(), i0, i0 + ni);
  const auto tiles = static_cast<Eigen::Index>(ctx.tileBox->size());
  for (Eigen::Index tj = 0; tj < tiles; ++tj) {
    if (squaredGap(blockBox, (*ctx.tileBox)[tj]) > ctx.gapLimit) continue;
    const Eigen::Index j0 = tj * kTileJ;
    for (Eigen::Index l = 0; l < ni; ++l) {
      const Eigen::Index i = i0 + l;
      const double cix = a.cx[i], ciy = a.cy[i], ciz = a.cz[i];
      const double nix = a.nx[i], niy = a.ny[i], niz = a.nz[i];
      RowAcc<W> q = acc[l];
      for (Eigen::Index j = j0; j < j0 + kTileJ; j += W) {
        using V = simd::Vd<W>;
        const V bx = simd::load<W>(&b.cx[j]), by = simd::load<W>(&b.cy[j]),
                bz = simd::load<W>(&b.cz[j]);
        const V dx = cix - bx, dy = ciy - by, dz = ciz - bz;
        const V e = simd::gauss<W>(dx * dx + dy * dy + dz * dz, s);
        const V mx = simd::load<W>(&b.nx[j]), my = simd::load<W>(&b.ny[j]),
                mz = simd::load<W>(&b.nz[j]);
        const V dot = nix * mx + niy * my + niz * mz;
        V k, t;
        if constexpr (kKind == FaceKernelKind::Varifold) {
          t = e * dot * simd::load<W>(&b.im[j]);
          k = t * dot;
        } else {
          t = e;
          k = e * dot;
        }
        q.s0 += k;
        if constexpr (kGrad) {
          q.sx += k * bx;
          q.sy += k * by;
          q.sz += k * bz;
          q.tx += t * mx;
          q.ty += t * my;
          q.tz += t * mz;
        }
      }
      acc[l] = q;
    }
  }
  for (Eigen::Index l = 0; l < ni; ++l) {
    const Eigen::Index i = i0 + l;
    const RowAcc<W>& q = acc[l];
    // The varifold's 1/|n_i| is constant over j: applied once here.
    const double w = kKind == FaceKernelKind::Varifold ? a.invNorm[i] : 1.0;
    const double s0 = simd::hsum<W>(q.s0);
    ctx.rowValue[i] = w * s0;
    if constexpr (kGrad) {
      const Eigen::RowVector3d c(a.cx[i], a.cy[i], a.cz[i]), n(a.nx[i], a.ny[i], a.nz[i]);
      const Eigen::RowVector3d sd(simd::hsum<W>(q.sx), simd::hsum<W>(q.sy), simd::hsum<W>(q.sz));
      const Eigen::RowVector3d tm(simd::hsum<W>(q.tx), simd::hsum<W>(q.ty), simd::hsum<W>(q.tz));
      // d/dc_i exp(-|c_i - d_j|^2 s) = -2 s (c_i - d_j) exp(...).
      ctx.gc->row(i) = (-2.0 * s * w) * (s0 * c - sd);
      if constexpr (kKind == FaceKernelKind::Varifold) {
        // d/dn (n.m)^2 / (|n||m|) = 2 (n.m) m / (|n||m|) - (n.m)^2 n / (|n|^3 |m|).
        ctx.gn->row(i) = (2.0 * w) * tm - (w * w * w * s0) * n;
      } else {
        ctx.gn->row(i) = tm;
      }
    }
  }
}

// The same body compiled for three instruction sets; the widest the CPU has is picked at run
// time (the build itself targets x86-64-v2, i.e. SSE4.2).
using BlockFn = void (*)(const SumContext&, Eigen::Index);

template <FaceKernelKind kKind, bool kGrad>
void blockSse(const SumContext& c, Eigen::Index b) {
  blockBody<2, kKind, kGrad>(c, b);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <FaceKernelKind kKind, bool kGrad>
__attribute__((target("avx2,fma"))) void blockAvx2(const SumContext& c, Eigen::Index b) {
  blockBody<4, kKind, kGrad>(c, b);
}
template <FaceKernelKind kKind, bool kGrad>
__attribute__((target("avx512f"))) void blockAvx512(const SumContext& c, Eigen::Index b) {
  blockBody<8, kKind, kGrad>(c, b);
}
#endif

template <FaceKernelKind kKind, bool kGrad>
BlockFn pickBlock() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const BlockFn fn = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f")) return &blockAvx512<kKind, kGrad>;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
      return &blockAvx2<kKind, kGrad>;
    return &blockSse<kKind, kGrad>;
  }();
  return fn;
#else
  return &blockSse<kKind, kGrad>;
#endif
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
  if (na == 0 || nb == 0) {
    if constexpr (kGrad) {
      gc->setZero();
      gn->setZero();
    }
    return 0.0;
  }
  const PaddedFaces pb(b);
  const Eigen::Index tiles = pb.padded / kTileJ;
  std::vector<Box> tileBox(static_cast<size_t>(tiles));
  for (Eigen::Index tj = 0; tj < tiles; ++tj) {
    tileBox[tj] = centreBox(b.cx.data(), b.cy.data(), b.cz.data(), tj * kTileJ,
                            std::min(nb, (tj + 1) * kTileJ));
  }
  const SumContext ctx{&a, &pb, s, &tileBox, kCutoff / s, rowValue.data(), gc, gn};
  const BlockFn block = pickBlock<kKind, kGrad>();
  const Eigen::Index blocks = (na + kBlockI - 1) / kBlockI;
  tbb::parallel_for(Eigen::Index(0), blocks, [&](Eigen::Index k) { block(ctx, k); });
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
