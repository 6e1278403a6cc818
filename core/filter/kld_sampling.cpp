#include "core/filter/kld_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <unordered_set>
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

namespace {

// The bin of particle i as one key: position 18 + 18 bits, heading offset 8, velocity
// 10 + 10 (each axis wraps: distinct bins share a key only 2^bits bins apart, e.g. 131 km
// at 0.5 m or 2560 deg at 10 deg).
struct BinKey {
  double inv_p, inv_v, inv_e;
  bool yaw;
  BinKey(const ParticleSet& set, const KldOptions& o)
      : inv_p(1.0 / std::max(o.bin_m, 1e-9)),
        inv_v(o.bin_mps > 0.0 ? 1.0 / o.bin_mps : 0.0),
        inv_e(o.bin_rad > 0.0 ? 1.0 / o.bin_rad : 0.0),
        yaw(o.bin_rad > 0.0 && set.heading && set.yaw.size() == set.size()) {}
  static std::uint64_t cell(double v, int bits) {
    const auto i = static_cast<std::int64_t>(std::floor(v));
    return static_cast<std::uint64_t>(i) & ((std::uint64_t{1} << bits) - 1);
  }
  std::uint64_t operator()(const ParticleSet& set, std::size_t i) const {
    std::uint64_t key = cell(set.x[i] * inv_p, 18) | (cell(set.y[i] * inv_p, 18) << 18);
    if (yaw) key |= cell(set.yaw[i] * inv_e, 8) << 36;
    if (inv_v > 0.0) key |= (cell(set.vx[i] * inv_v, 10) << 44) | (cell(set.vy[i] * inv_v, 10) << 54);
    return key;
  }
};

template <typename Index>
std::size_t count_bins(const ParticleSet& set, std::size_t n, const Index& index, const KldOptions& o) {
  if (n == 0) return 0;
  const BinKey bin(set, o);
  std::vector<std::uint64_t> keys(n);
  tbb::parallel_for(std::size_t{0}, particle_chunks(n), [&](std::size_t c) {
    const std::size_t e = std::min(n, (c + 1) * kParticleChunk);
    for (std::size_t k = c * kParticleChunk; k < e; ++k) keys[k] = bin(set, index(k));
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

}  // namespace

std::size_t count_occupied_bins(const ParticleSet& set, std::span<const std::uint32_t> indices,
                                const KldOptions& o) {
  return count_bins(set, indices.size(), [&](std::size_t k) { return static_cast<std::size_t>(indices[k]); }, o);
}

std::size_t count_occupied_bins(const ParticleSet& set, std::size_t n, const KldOptions& o) {
  return count_bins(set, std::min(n, set.size()), [](std::size_t k) { return k; }, o);
}

std::size_t kld_prefix_size(const ParticleSet& set, const KldOptions& o, std::size_t step) {
  const std::size_t n = std::min(set.size(), std::max(o.max_particles, std::size_t{1}));
  step = std::max<std::size_t>(step, 1);
  const BinKey bin(set, o);
  std::unordered_set<std::uint64_t> seen;
  for (std::size_t m = 0; m < n;) {
    const std::size_t e = std::min(n, m + step);
    for (; m < e; ++m) seen.insert(bin(set, m));
    if (m >= kld_particle_count(seen.size(), o)) return m;
  }
  return n;
}

}  // namespace luxloc
