#include "core/filter/genetic_resampler.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/parallel_for.h>
#include <vector>

#include "core/filter/fast_rng.hpp"
#include "core/filter/lane_rng.hpp"

namespace luxloc {
namespace {

template <typename F>
void for_each_chunk(std::size_t n, std::size_t chunk, F&& f) {
  const std::size_t chunks = (n + chunk - 1) / chunk;
  if (chunks <= 1) {
    if (n) f(std::size_t{0}, std::size_t{0}, n);
    return;
  }
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) { f(c, c * chunk, std::min(n, (c + 1) * chunk)); });
}

}  // namespace

GeneticStats genetic_resample(ParticleSet& set, std::span<const float> log_w, float log_w_max,
                              const GeneticOptions& o, std::uint64_t seed, std::uint64_t step) {
  GeneticStats stats;
  const std::size_t n = set.size();
  if (n == 0 || log_w.size() != n || !std::isfinite(log_w_max)) return stats;
  // B.5a: excellent iff w_i / w_max >= threshold, i.e. log w_i - log w_max >= log threshold.
  const float log_thr = static_cast<float>(std::log(std::clamp(o.threshold, 1e-30, 1.0)));
  const auto excellent = [&](std::size_t i) { return log_w[i] - log_w_max >= log_thr; };

  // Excellent particles, in index order: per-chunk counts, then a serial prefix.
  const std::size_t chunks = particle_chunks(n);
  std::vector<std::size_t> offset(chunks + 1, 0);
  for_each_chunk(n, kParticleChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    std::size_t k = 0;
    for (std::size_t i = b; i < e; ++i) k += excellent(i);
    offset[c + 1] = k;
  });
  for (std::size_t c = 0; c < chunks; ++c) offset[c + 1] += offset[c];
  const std::size_t n_exc = offset[chunks];
  stats.excellent = n_exc;
  stats.decayed = n - n_exc;
  if (n_exc == 0 || n_exc == n) return stats;

  // Their weights relative to the largest, in [threshold, 1]. A partner is drawn in
  // proportion to its weight by rejection: pick one uniformly, keep it with probability
  // w / 1 — at least `threshold` of the picks are kept, and a pick is one random read.
  struct Candidate {
    std::uint32_t index;
    float w_rel;
  };
  std::vector<Candidate> exc(n_exc);
  for_each_chunk(n, kParticleChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    std::size_t k = offset[c];
    for (std::size_t i = b; i < e; ++i)
      if (excellent(i)) exc[k++] = {static_cast<std::uint32_t>(i), std::exp(log_w[i] - log_w_max)};
  });
  const double dn_exc = static_cast<double>(n_exc);

  // B.5c: one r_k per resampling step.
  FastRng step_rng = FastRng::stream(seed, step, 0x6E6E7ull);
  const double r_k = step_rng.uniform();
  stats.r_k = r_k;
  const float alpha = static_cast<float>(o.alpha);
  const float s_p = static_cast<float>(r_k * o.mutation_position_m), s_v = static_cast<float>(r_k * o.mutation_velocity_mps);
  const float p_mut = static_cast<float>(o.mutation_probability);
  std::vector<std::size_t> mutated(chunks, 0);
  // Excellent particles are never written, so decayed ones can be rewritten in place.
  // Blocks of 256: first every partner (independent random reads, which the CPU
  // overlaps), then the crossover; random numbers drawn eight lanes at a time.
  constexpr std::size_t kBlock = 256;
  for_each_chunk(n, kParticleChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(seed, step, c + 1);
    FastRng retry = FastRng::stream(seed, step, 0x7E7E7ull + c);
    alignas(32) float uni[3 * kBlock];
    alignas(32) float nrm[4 * kBlock];
    std::uint32_t partner[kBlock];
    std::size_t m = 0;
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_uniform(uni, 3 * kBlock);
      rng.fill_normal(nrm, 4 * kBlock);
      for (std::size_t q = 0; q < len; ++q) {
        const std::size_t i = blk + q;
        if (excellent(i)) {
          partner[q] = static_cast<std::uint32_t>(i);
          continue;
        }
        double u = uni[q], v = uni[2 * kBlock + q];
        for (;;) {
          const Candidate& cand = exc[std::min(n_exc - 1, static_cast<std::size_t>(u * dn_exc))];
          if (v < static_cast<double>(cand.w_rel)) {
            partner[q] = cand.index;
            break;
          }
          u = retry.uniform();
          v = retry.uniform();
        }
      }
      for (std::size_t q = 0; q < len; ++q) {
        const std::size_t i = blk + q;
        const std::uint32_t j = partner[q];
        if (j == i) continue;  // excellent
        // B.5b crossover on the whole state.
        float x = alpha * set.x[j] + (1.0f - alpha) * set.x[i];
        float y = alpha * set.y[j] + (1.0f - alpha) * set.y[i];
        float vx = alpha * set.vx[j] + (1.0f - alpha) * set.vx[i];
        float vy = alpha * set.vy[j] + (1.0f - alpha) * set.vy[i];
        // B.5c mutation.
        if (uni[kBlock + q] < p_mut) {
          x += s_p * nrm[q];
          y += s_p * nrm[kBlock + q];
          vx += s_v * nrm[2 * kBlock + q];
          vy += s_v * nrm[3 * kBlock + q];
          ++m;
        }
        set.x[i] = x;
        set.y[i] = y;
        set.vx[i] = vx;
        set.vy[i] = vy;
        if (set.gait) {
          // The gait calibration crosses over with the rest of the state (no mutation:
          // the motion model's random walk keeps it diverse).
          set.ks[i] = alpha * set.ks[j] + (1.0f - alpha) * set.ks[i];
          set.dpsi[i] = alpha * set.dpsi[j] + (1.0f - alpha) * set.dpsi[i];
          set.kturn[i] = alpha * set.kturn[j] + (1.0f - alpha) * set.kturn[i];
        }
        if (set.heading) set.yaw[i] = alpha * set.yaw[j] + (1.0f - alpha) * set.yaw[i];
      }
    }
    mutated[c] = m;
  });
  for (std::size_t m : mutated) stats.mutated += m;
  return stats;
}

}  // namespace luxloc
