#pragma once
// KLD-sampling (Fox 2003, as in ROS AMCL): choose the number of particles so that, with
// probability 1 - delta, the K-L divergence between the sample-based posterior and the
// true one stays below epsilon, given k occupied histogram bins:
//   n = (k - 1) / (2 eps) * (1 - 2 / (9 (k - 1)) + sqrt(2 / (9 (k - 1))) z_{1-delta})^3.
// A converged filter occupies few bins and needs few particles; a spread one needs many.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/filter/particle_set.hpp"

namespace luxloc {

struct KldOptions {
  bool enabled = false;
  double bin_m = 0.05;    // position bin size (AMCL uses 0.5 m; our fixes are cm-level)
  double bin_mps = 0.0;   // velocity bin size; 0: bins over position only
  double bin_rad = 0.0;   // heading-offset bin size (set.yaw, when the set has it); 0: none
  double epsilon = 0.05;  // AMCL kld_err (0.01 at decimetre bins)
  double z = 2.326;       // upper standard-normal quantile z_{1-delta} (delta = 0.01)
  std::size_t min_particles = 500;
  std::size_t max_particles = 100000;
};

// The KLD bound for k occupied bins, clamped to [min_particles, max_particles].
std::size_t kld_particle_count(std::size_t occupied_bins, const KldOptions& options);

// Number of distinct bins occupied by the particles set.x[i], ... for i in `indices`
// (repeats allowed). Deterministic; parallel for large sets.
std::size_t count_occupied_bins(const ParticleSet& set, std::span<const std::uint32_t> indices,
                                const KldOptions& options);
// The same over the first n particles of the set.
std::size_t count_occupied_bins(const ParticleSet& set, std::size_t n, const KldOptions& options);

// Fox's KLD-sampling of a set already drawn from the proposal in random order (every prefix
// a fair sample of it): the shortest prefix, in steps of `step` particles, that is at least
// the KLD bound for the bins it occupies (options.max_particles at most, the whole set when
// shorter). Sizes a global search's first set (ParticleFilter::initialize_around, _uniform).
std::size_t kld_prefix_size(const ParticleSet& set, const KldOptions& options, std::size_t step = 256);

}  // namespace luxloc
