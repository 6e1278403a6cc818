#pragma once
// Genetic resampling against sample impoverishment (SEEDS.md B.5): instead of copying
// heavy particles, keep the "excellent" ones as they are and move each "decayed" one
// towards an excellent partner (crossover), then perturb it (mutation). The new set is
// excellent ∪ mutated, with equal weights; its size does not change.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/filter/particle_set.hpp"

namespace luxloc {

struct GeneticOptions {
  // B.5a: a particle is excellent when w_i / max_j w_j >= threshold (seed: [0.6, 0.8], 0.65).
  double threshold = 0.65;
  // B.5b: x' = alpha x_excellent + (1 - alpha) x_decayed (seed: [0.6, 0.8], 0.7); the
  // partner is drawn among the excellent particles in proportion to their weights.
  double alpha = 0.7;
  // B.5c: each crossed particle mutates with this probability (seed: 0.5):
  // x'' = x' + r_k * scale * n, r_k uniform in [0, 1] drawn once per resampling step (the
  // seed's "per step"), n a standard normal per state component (zero-mean direction).
  double mutation_probability = 0.5;
  double mutation_position_m = 0.05;    // scale on x, y
  double mutation_velocity_mps = 0.05;  // scale on vx, vy
  // Not in the seed: the crossover pulls each decayed particle 70 % of the way to an
  // excellent one and the new set is equally weighted, so every resampling shrinks the
  // position spread below the weighted posterior's it came from; resampled after every
  // correction, the cloud collapses and the filter believes itself (tuning seeds 1-10,
  // IMU + one UWB station: 56 % of the poses within their 95 % ellipse, 1 Hz fixes 56 %).
  // The decayed particles also keep 1 - alpha of their old place, so the set's mean lags
  // the weighted posterior's. true: after the genetic step the set gets the posterior's first
  // two moments back: every component shifted by the mean it lost, the position roughened
  // (Gordon et al. 1993) by a Gaussian of the weighted covariance before less the equal-weight
  // covariance after (its negative part dropped), velocity, gait (ks, dpsi, kturn) and yaw
  // offset by the variance each lost (ParticleFilter::restore_spread; docs/FILTERS.md: on
  // hold-out walkers 53-54 % -> 94-95 % within the 95 % ellipse, ATE 0.141 -> 0.071 m on UWB).
  bool preserve_spread = true;
};

struct GeneticStats {
  std::size_t excellent = 0;
  std::size_t decayed = 0;
  std::size_t mutated = 0;
  double r_k = 0.0;
};

// log_w: the particles' log weights (any common offset); log_w_max: their maximum.
// Rewrites the decayed particles of `set` in place; deterministic for (seed, step),
// whatever the thread count.
GeneticStats genetic_resample(ParticleSet& set, std::span<const float> log_w, float log_w_max,
                              const GeneticOptions& options, std::uint64_t seed, std::uint64_t step);

}  // namespace luxloc
