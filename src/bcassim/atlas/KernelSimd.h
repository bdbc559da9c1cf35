// Portable SIMD pieces for the kernel sums of eqs. 4.4-4.5 (GCC/Clang vector extensions): W-wide
// double vectors, the vectorised fastExp, and the run-time choice of the widest instruction set
// (the build targets x86-64-v2; AVX2+FMA or AVX-512 bodies are compiled alongside).
#pragma once
#include <cstring>

#include "bcassim/atlas/FastExp.h"

// The helpers below are always inlined into their callers, so the vector-return ABI notes of
// GCC do not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace bcassim::simd {

// Explicit specialisations: GCC ignores vector_size on an alias template with a dependent size.
template <int W>
struct VecTypes;
template <>
struct VecTypes<2> {
  typedef double D __attribute__((vector_size(16)));
  typedef long long I __attribute__((vector_size(16)));
};
template <>
struct VecTypes<4> {
  typedef double D __attribute__((vector_size(32)));
  typedef long long I __attribute__((vector_size(32)));
};
template <>
struct VecTypes<8> {
  typedef double D __attribute__((vector_size(64)));
  typedef long long I __attribute__((vector_size(64)));
};
template <int W>
using Vd = typename VecTypes<W>::D;
template <int W>
using Vi = typename VecTypes<W>::I;

template <int W>
__attribute__((always_inline)) inline Vd<W> load(const double* p) {
  Vd<W> v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

template <int W>
__attribute__((always_inline)) inline void store(double* p, Vd<W> v) {
  std::memcpy(p, &v, sizeof(v));
}

static_assert(sizeof(Vd<8>) == 64 && sizeof(Vi<4>) == 32, "vector extensions unavailable");

template <int W>
__attribute__((always_inline)) inline double hsum(Vd<W> v) {
  double lanes[W] = {};
  std::memcpy(lanes, &v, sizeof(v));
  double s = 0.0;
  for (int l = 0; l < W; ++l) s += lanes[l];
  return s;
}

// exp(-d2 * s) for d2 >= 0: the argument is clamped at kFastExpMin, then detail::fastExp's
// algorithm on a vector (fastExpKernel: the same code).
template <int W>
__attribute__((always_inline)) inline Vd<W> gauss(Vd<W> d2, double s) {
  const Vd<W> minArg = Vd<W>{} + detail::kFastExpMin;
  Vd<W> x = -d2 * s;
  x = x < minArg ? minArg : x;
  return detail::fastExpKernel<Vd<W>, Vi<W>>(x);
}

enum class Isa { Sse, Avx2, Avx512 };

// The widest instruction set this CPU runs (checked once).
inline Isa bestIsa() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const Isa isa = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f")) return Isa::Avx512;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return Isa::Avx2;
    return Isa::Sse;
  }();
  return isa;
#else
  return Isa::Sse;
#endif
}

}  // namespace bcassim::simd

#pragma GCC diagnostic pop

// Defines NAME(args) dispatching to NAME##Body<W>(args) compiled for SSE (W = 2), AVX2+FMA (4)
// and AVX-512 (8). BODY must be an always_inline template on int W.
// PARAMS and ARGS are parenthesised lists spliced after a name: they cannot take parentheses.
// NOLINTBEGIN(bugprone-macro-parentheses)
#if defined(__x86_64__) && defined(__GNUC__)
#define BCASSIM_SIMD_DISPATCH(NAME, BODY, PARAMS, ARGS)                                \
  static void NAME##Sse PARAMS { BODY<2> ARGS; }                                       \
  __attribute__((target("avx2,fma"))) static void NAME##Avx2 PARAMS { BODY<4> ARGS; }  \
  __attribute__((target("avx512f"))) static void NAME##Avx512 PARAMS { BODY<8> ARGS; } \
  static void NAME PARAMS {                                                            \
    switch (::bcassim::simd::bestIsa()) {                                              \
      case ::bcassim::simd::Isa::Avx512:                                               \
        NAME##Avx512 ARGS;                                                             \
        break;                                                                         \
      case ::bcassim::simd::Isa::Avx2:                                                 \
        NAME##Avx2 ARGS;                                                               \
        break;                                                                         \
      default:                                                                         \
        NAME##Sse ARGS;                                                                \
    }                                                                                  \
  }
#else
#define BCASSIM_SIMD_DISPATCH(NAME, BODY, PARAMS, ARGS) \
  static void NAME PARAMS { BODY<2> ARGS; }
#endif
// NOLINTEND(bugprone-macro-parentheses)
