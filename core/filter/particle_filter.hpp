#pragma once
// Sequential importance resampling particle filter over the planar state
// (x, y, vx, vy) — SEEDS.md A, S3. Particles are a structure of arrays; propagation,
// weighting and normalisation run on TBB over fixed-size chunks, each with its own
// random stream keyed by (seed, step, chunk), so results do not depend on thread count.
// Weights are kept in log space; a correction that every particle finds implausible is
// gated, and a filter that keeps rejecting fixes re-initialises around them.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "core/filter/planar_filter.hpp"
#include "core/filter/resampling.hpp"

namespace luxloc {

struct ParticleFilterOptions {
  std::size_t particles = 2000;
  std::uint64_t seed = 1;
  ResamplingScheme scheme = ResamplingScheme::Systematic;
  // Resample when n_eff < threshold * N; seed A resamples after every correction (1.0+).
  double resample_threshold = 0.5;
  bool resample_every_correction = false;  // seed A, S303
  // Process noise: white acceleration noise PSD (m^2/s^3) on the velocity.
  double accel_noise_psd = 0.5;
  // Velocity decay time constant (s): keeps velocity bounded when acceleration input is
  // biased (gravity leaking through attitude error). <= 0 disables.
  double velocity_tau_s = 3.0;
  double max_speed = 3.0;        // m/s, particles above are clamped (a walking device)
  double init_speed_sigma = 0.3; // m/s
  // After resampling, jitter positions by this many metres (1 sigma) against impoverishment.
  double roughening_m = 0.003;
  // Lost-track recovery: this many consecutive gated fixes re-initialise the filter.
  int max_consecutive_rejections = 8;
};

// Structure of arrays: one vector per state component.
struct ParticleSet {
  std::vector<double> x, y, vx, vy;
  std::vector<double> log_w;  // unnormalised log weights
  std::vector<double> w;      // normalised weights (valid after normalize())
  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n); y.resize(n); vx.resize(n); vy.resize(n); log_w.resize(n); w.resize(n);
  }
};

class ParticleFilter final : public PlanarFilter {
 public:
  explicit ParticleFilter(const ParticleFilterOptions& options = {});

  void initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) override;
  bool initialized() const override { return initialized_; }
  void predict(const MotionInput& u) override;
  CorrectionResult correct(const PositionMeasurement& m) override;
  PlanarEstimate estimate() const override { return estimate_; }

  // Multiplies every particle's weight by exp(log_likelihood(x, y)) — the generic
  // measurement update (tight coupling passes a reprojection likelihood here). Returns
  // false (and leaves the weights alone) when every particle's likelihood underflows.
  template <typename LogLikelihood>
  bool weigh(const LogLikelihood& log_likelihood);

  // Normalises the weights (log-sum-exp), updates n_eff and the estimate, resamples if
  // needed. False when the weights degenerated (all -inf / NaN).
  bool normalize_and_resample();

  const ParticleSet& particles() const { return set_; }
  const ParticleFilterOptions& options() const { return options_; }
  double n_eff() const { return n_eff_; }
  std::uint64_t resample_count() const { return resamples_; }
  std::uint64_t reinit_count() const { return reinits_; }
  std::uint64_t rejected_count() const { return rejected_; }

 private:
  void update_estimate();
  void resample_now();

  ParticleFilterOptions options_;
  ParticleSet set_;
  ParticleSet scratch_;
  std::vector<std::uint32_t> ancestors_;
  PlanarEstimate estimate_;
  double n_eff_ = 0.0;
  std::uint64_t step_ = 0;
  std::uint64_t resamples_ = 0, reinits_ = 0, rejected_ = 0;
  int consecutive_rejections_ = 0;
  bool initialized_ = false;
};

}  // namespace luxloc

#include "core/filter/particle_filter_weigh.hpp"
