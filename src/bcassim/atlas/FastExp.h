// exp(x) for x <= 0 written so that loops over it vectorise (no libm call): the Gaussian factors
// of the kernel sums of eqs. 4.4-4.5 are the hot spot of the atlas code.
#pragma once
#include <cstdint>

namespace bcassim::detail {

// Lower end of fastExp's domain; exp(-700) ~ 1e-304 is negligible next to any kernel sum, so
// callers clamp there.
constexpr double kFastExpMin = -700.0;

// Relative error below 4e-16 for x in [kFastExpMin, 0] (undefined outside). The clamp is left to
// the caller, in a separate loop: GCC 12 does not vectorise a clamp and the bit tricks together.
// Range reduction x = k ln2 + r, |r| <= ln2/2, a degree-12 Taylor polynomial of e^r, then 2^k
// assembled in the exponent bits. T is double (with I = std::uint64_t) or a GCC vector of
// doubles (with the matching vector of 64-bit integers, KernelSimd.h): one algorithm for both.
// Always inlined (into SIMD bodies compiled for AVX2 / AVX-512 too), so GCC's notes on the
// vector-return ABI do not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class T, class I>
__attribute__((always_inline)) inline T fastExpKernel(T x) {
  constexpr double kLog2e = 1.4426950408889634;
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  constexpr double kShifter = 6755399441055744.0;  // 1.5 * 2^52: rounds k into the low bits
  const T t = x * kLog2e + kShifter;
  const T k = t - kShifter;
  const T r = (x - k * kLn2Hi) - k * kLn2Lo;
  T p = r * (1.0 / 479001600.0) + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  // The low 12 bits of t's pattern hold k mod 4096, so (bits + 1023) << 52 is the pattern of 2^k.
  const I scaleBits = (__builtin_bit_cast(I, t) + 1023) << 52;
  return p * __builtin_bit_cast(T, scaleBits);
}

#pragma GCC diagnostic pop

inline double fastExp(double x) { return fastExpKernel<double, std::uint64_t>(x); }

}  // namespace bcassim::detail
