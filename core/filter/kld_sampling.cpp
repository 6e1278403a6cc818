#include "core/filter/kld_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <vector>

namespace luxloc {

std::size_t kld_particle_count(std::size_t occupied_bins, const KldOptions& o) {
  const std::size_t lo = std::max<std::size_t>(o.min_particles, 1);
  const std::size_t hi = std::max(lo, o.max_particles);
  if (occupied_bins <= 1) return lo;
  const double k1 = static_cast<double>(occupied_bins - 1);
  const double a = 2.0 / (9.0 * k1);
  const double b = 1.0 - a + std::sqrt(a) * o.z;
  const double n = k1 / (2.0 * std::max(o.epsilon, 1e-9)) * b * b * b;
  if (!(n < static_cast<double>(hi))) return hi;  // also catches NaN
  return std::clamp(static_cast<std::size_t>(std::ceil(n)), lo, hi);
}

std::size_t count_occupied_bins(const ParticleSet& set, std::span<const std::uint32_t> indices,
                                const KldOptions& o) {
  const std::size_t n = indices.size();
  if (n == 0) return 0;
  const double inv_p = 1.0 / std::max(o.bin_m, 1e-9);
  const double inv_v = o.bin_mps > 0.0 ? 1.0 / o.bin_mps : 0.0;
  // Bin index per axis packed into 64 bits (21 + 21 bits of position, 11 + 11 of
  // velocity): distinct bins differ in their key unless 2^21 bins apart.
  const auto cell = [](double v, int bits) {
    const auto i = static_cast<std::int64_t>(std::floor(v));
    return static_cast<std::uint64_t>(i) & ((std::uint64_t{1} << bits) - 1);
  };
  std::vector<std::uint64_t> keys(n);
  tbb::parallel_for(std::size_t{0}, particle_chunks(n), [&](std::size_t c) {
    const std::size_t e = std::min(n, (c + 1) * kParticleChunk);
    for (std::size_t k = c * kParticleChunk; k < e; ++k) {
      const std::uint32_t i = indices[k];
      std::uint64_t key = cell(set.x[i] * inv_p, 21) | (cell(set.y[i] * inv_p, 21) << 21);
      if (inv_v > 0.0) key |= (cell(set.vx[i] * inv_v, 11) << 42) | (cell(set.vy[i] * inv_v, 11) << 53);
      keys[k] = key;
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

}  // namespace luxloc
