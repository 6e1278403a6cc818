#pragma once
// Eight-lane float/int vectors (GCC/Clang vector extensions: one AVX2 register each under
// -march=x86-64-v3, two SSE registers otherwise) and the few transcendental kernels the
// particle filter needs in its hot loops. Eigen 3.4 vectorises exp/log on plain arrays but
// not inside select(), and a lane loop over std::exp stays scalar (errno semantics).
#include <cstdint>
#include <cstring>
#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace luxloc::simd8 {

using U8 = std::uint32_t __attribute__((vector_size(32)));
using I8 = std::int32_t __attribute__((vector_size(32)));
using F8 = float __attribute__((vector_size(32)));

template <typename To, typename From>
inline To bits(const From& v) {
  static_assert(sizeof(To) == sizeof(From));
  To t;
  std::memcpy(&t, &v, sizeof t);
  return t;
}
inline F8 load(const float* p) {
  F8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, F8 v) { std::memcpy(p, &v, sizeof v); }
inline F8 splat(float f) { return F8{} + f; }

// Lanes shifted up by K (lane l gets lane l - K, the first K lanes get zero): the steps of
// an in-register prefix sum / maximum.
template <int K, typename V>
inline V shift_up(V v) {
  static_assert(K == 1 || K == 2 || K == 4);
#if defined(__clang__)
  if constexpr (K == 1) return __builtin_shufflevector(v, V{}, 8, 0, 1, 2, 3, 4, 5, 6);
  if constexpr (K == 2) return __builtin_shufflevector(v, V{}, 8, 8, 0, 1, 2, 3, 4, 5);
  if constexpr (K == 4) return __builtin_shufflevector(v, V{}, 8, 8, 8, 8, 0, 1, 2, 3);
#else
  if constexpr (K == 1) return __builtin_shuffle(v, V{}, I8{8, 0, 1, 2, 3, 4, 5, 6});
  if constexpr (K == 2) return __builtin_shuffle(v, V{}, I8{8, 8, 0, 1, 2, 3, 4, 5});
  if constexpr (K == 4) return __builtin_shuffle(v, V{}, I8{8, 8, 8, 8, 0, 1, 2, 3});
#endif
}

// exp(x) for x <= 0 (rel. error ~2e-7, Cephes expf polynomial); exactly 0 below -87, where
// single precision goes denormal — so -inf (a dead particle) gives 0.
inline F8 exp_nonpositive(F8 x) {
  const I8 dead = x < -87.0f;
  x = dead ? splat(-87.0f) : x;
  // n = round(x / ln 2) (x <= 0: truncation of t - 0.5, corrected to a floor)
  const F8 t = x * 1.44269504f + 0.5f;
  I8 n = __builtin_convertvector(t, I8);
  n = __builtin_convertvector(n, F8) > t ? n - 1 : n;
  const F8 fn = __builtin_convertvector(n, F8);
  const F8 r = x - fn * 0.693359375f + fn * 2.12194440e-4f;
  F8 p = 1.9875691500e-4f * r + 1.3981999507e-3f;
  p = p * r + 8.3334519073e-3f;
  p = p * r + 4.1665795894e-2f;
  p = p * r + 1.6666665459e-1f;
  p = p * r + 5.0000001201e-1f;
  const F8 e = p * (r * r) + r + 1.0f;
  const F8 scaled = e * bits<F8>((n + 127) << 23);
  return dead ? F8{} : scaled;
}

// ln(u) for u > 0 (finite, normal): exponent plus Cephes' logf polynomial on the mantissa
// folded into [0.707, 1.414) — no division (rel. error ~1e-7).
inline F8 log_positive(F8 u) {
  const I8 ub = bits<I8>(u);
  I8 e = ((ub >> 23) & 0xff) - 127;
  F8 m = bits<F8>((ub & 0x7fffff) | 0x3f800000);  // [1, 2)
  const I8 big = m > 1.41421356f;
  m = big ? m * 0.5f : m;
  e = big ? e + 1 : e;
  const F8 x = m - 1.0f;
  const F8 z = x * x;
  F8 p = 7.0376836292e-2f * x - 1.1514610310e-1f;
  p = p * x + 1.1676998740e-1f;
  p = p * x - 1.2420140846e-1f;
  p = p * x + 1.4249322787e-1f;
  p = p * x - 1.6668057665e-1f;
  p = p * x + 2.0000714765e-1f;
  p = p * x - 2.4999993993e-1f;
  p = p * x + 3.3333331174e-1f;
  const F8 fe = __builtin_convertvector(e, F8);
  const F8 y = x * z * p - 2.12194440e-4f * fe - 0.5f * z;
  return x + y + 0.693359375f * fe;
}

// sqrt(x) for x >= 0. With AVX the hardware square root (one instruction, correctly
// rounded: a lane loop over std::sqrt would stay scalar, errno-bound); otherwise
// x * rsqrt(x), rsqrt from the bit-level estimate plus three Newton steps (rel. error
// < 1e-7, a dependent chain of twelve multiplies: it was half of the propagation's time).
// 0 for x == 0.
inline F8 sqrt_nonnegative(F8 x) {
#if defined(__AVX__)
  const __m256 r = _mm256_sqrt_ps(bits<__m256>(x));
  return bits<F8>(r);
#else
  const F8 xs = x < 1e-30f ? splat(1e-30f) : x;
  F8 y = bits<F8>(0x5f375a86 - (bits<I8>(xs) >> 1));
  const F8 h = 0.5f * xs;
  y = y * (1.5f - h * y * y);
  y = y * (1.5f - h * y * y);
  y = y * (1.5f - h * y * y);
  return x < 1e-30f ? F8{} : xs * y;
#endif
}

}  // namespace luxloc::simd8
