#pragma once
// Eight xoshiro128+ generators side by side (one per AVX2 lane) and a Box-Muller normal
// generator on eight-lane polynomial log/sqrt/sin/cos (simd8.hpp): the particle filter
// draws two normals per particle per step, and at 1M particles a scalar generator
// (FastRng::normal, ~10 ns a pair) would be most of the step. Here a normal costs ~1 ns.
// Seeded from FastRng::stream(seed, a, b), so a fixed chunk of particles gets the same
// numbers whatever thread runs it.
#include <cstddef>
#include <cstdint>

#include "core/filter/fast_rng.hpp"
#include "core/filter/simd8.hpp"

namespace luxloc {

class LaneRng {
 public:
  static constexpr std::size_t kLanes = 8;

  LaneRng(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0) {
    FastRng base = FastRng::stream(seed, a, b);
    for (std::size_t l = 0; l < kLanes; ++l) {
      s0_[l] = static_cast<std::uint32_t>(base.next() >> 32);
      s1_[l] = static_cast<std::uint32_t>(base.next() >> 32);
      s2_[l] = static_cast<std::uint32_t>(base.next() >> 32);
      s3_[l] = static_cast<std::uint32_t>(base.next() >> 32) | 1u;  // never the all-zero state
    }
  }

  // Uniforms in (0, 1) (never 0, so log() is safe); n must be a multiple of kLanes.
  void fill_uniform(float* out, std::size_t n) {
    for (std::size_t i = 0; i < n; i += kLanes) {
      // Top 24 bits (xoshiro128+'s low bits are its weak ones), centred in their cell.
      simd8::store(out + i, (__builtin_convertvector(__builtin_convertvector(next() >> 8, I8), F8) + 0.5f) * 0x1.0p-24f);
    }
  }

  // Standard normals (Box-Muller, both values of each pair used); n must be a multiple
  // of 2 * kLanes. log, sqrt and sin/cos are short polynomials (rel. error < 1e-6)
  // evaluated eight lanes at a time; the angle comes straight from the random bits
  // (quadrant from the top two, the offset within it from the next 22), so no range
  // reduction is needed.
  void fill_normal(float* out, std::size_t n) {
    for (std::size_t i = 0; i + 2 * kLanes <= n; i += 2 * kLanes) {
      const F8 r = simd8::sqrt_nonnegative(log_unit(next()) * -2.0f);
      F8 c, s;
      sincos_uniform(next(), c, s);
      simd8::store(out + i, r * c);
      simd8::store(out + i + kLanes, r * s);
    }
  }

  // Zero-mean unit-variance triangular variates (sum of two 16-bit uniforms, scaled by
  // sqrt(6)): a smooth, bounded kernel at an eighth of a normal's cost — for roughening,
  // where the kernel's shape does not matter but its cost does. n: a multiple of kLanes.
  void fill_triangular(float* out, std::size_t n) {
    for (std::size_t i = 0; i < n; i += kLanes) {
      const U8 r = next();
      const F8 hi = __builtin_convertvector(__builtin_convertvector(r >> 16, I8), F8);
      const F8 lo = __builtin_convertvector(__builtin_convertvector(r & 0xffffu, I8), F8);
      simd8::store(out + i, ((hi + lo + 1.0f) * 0x1.0p-16f - 1.0f) * 2.44948974f);
    }
  }

  static constexpr std::size_t round_up(std::size_t n, std::size_t to) { return (n + to - 1) / to * to; }

 private:
  using U8 = simd8::U8;
  using I8 = simd8::I8;
  using F8 = simd8::F8;

  U8 next() {
    const U8 r = s0_ + s3_;
    const U8 t = s1_ << 9;
    s2_ ^= s0_;
    s3_ ^= s1_;
    s1_ ^= s2_;
    s0_ ^= s3_;
    s2_ ^= t;
    s3_ = (s3_ << 11) | (s3_ >> 21);
    return r;
  }
  U8 s0_, s1_, s2_, s3_;

  static F8 log_unit(U8 r) {
    return simd8::log_positive((__builtin_convertvector(__builtin_convertvector(r >> 8, I8), F8) + 0.5f) * 0x1.0p-24f);
  }

  // (cos, sin) of an angle uniform on the circle: quadrant q from bits 31..30, offset
  // theta in (-pi/4, pi/4) from bits 29..8; Taylor polynomials to theta^8 / theta^7.
  static void sincos_uniform(U8 r, F8& c, F8& s) {
    const F8 th = (__builtin_convertvector(__builtin_convertvector((r >> 8) & 0x3fffffu, I8), F8) + 0.5f) *
                      (0x1.0p-22f * 1.57079633f) -
                  0.785398163f;
    const F8 t2 = th * th;
    const F8 sn = th * (1.0f + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040))));
    const F8 cs = 1.0f + t2 * (-0.5f + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320))));
    const U8 q = r >> 30;
    const I8 odd = (q & 1u) != 0u;
    const U8 flip = (q & 2u) << 30;  // quadrants 2, 3: negate both
    c = simd8::bits<F8>(simd8::bits<U8>(odd ? -sn : cs) ^ flip);
    s = simd8::bits<F8>(simd8::bits<U8>(odd ? cs : sn) ^ flip);
  }
};

}  // namespace luxloc
