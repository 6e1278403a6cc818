#pragma once
// Every random draw of a simulation derives from the user's --seed: each independent stream
// (IMU noise, biases, LED phases, frame k's noise) gets its own std::mt19937_64 seeded from a
// hash of (seed, stream, index). Frames can then be rendered in any order, on any thread,
// and still be bit-identical for the same seed.
#include <cstdint>
#include <random>

namespace luxloc::sim {

enum class RandomStream : std::uint64_t {
  imu_biases = 1, led_phases = 2, imu_noise = 3, frame = 4, uwb = 5, floor_texture = 6, imu_scale = 7,
  imu_bias_walk = 8, uwb_bias = 9, fixes = 16, walker = 17, world = 18
};

// SplitMix64 finaliser (Steele et al. 2014): a bijective, well-mixing 64-bit hash.
inline constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::mt19937_64 make_rng(std::uint64_t seed, RandomStream stream, std::uint64_t index = 0) {
  const std::uint64_t h = splitmix64(splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(stream)) ^ index);
  return std::mt19937_64(h);
}

}  // namespace luxloc::sim
