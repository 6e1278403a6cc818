#include "core/filter/particle_filter.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "core/filter/fast_rng.hpp"
#include "core/filter/lane_rng.hpp"
#include "core/filter/simd8.hpp"

namespace luxloc {
namespace {

// Block of particles processed with Eigen array expressions: stays in L1, and its start is
// 32-byte aligned (chunks and blocks start at multiples of 256 floats).
constexpr std::size_t kBlock = 256;
static_assert(kParticleChunk % kBlock == 0);
using BlockF = Eigen::Array<float, Eigen::Dynamic, 1, 0, static_cast<int>(kBlock), 1>;
using MapF = Eigen::Map<Eigen::ArrayXf, Eigen::AlignedMax>;
using CMapF = Eigen::Map<const Eigen::ArrayXf, Eigen::AlignedMax>;
using CMapU = Eigen::Map<const Eigen::ArrayXf>;  // unaligned (noise halves)

constexpr float kNegInf = -std::numeric_limits<float>::infinity();
// Below this exp() is denormal or zero in single precision: count it as zero.
constexpr float kExpFloor = -87.0f;

Eigen::Index idx(std::size_t n) { return static_cast<Eigen::Index>(n); }

}  // namespace

void ParticleFilter::Moments::add(const Moments& o) {
  w += o.w; x += o.x; y += o.y; vx += o.vx; vy += o.vy; xx += o.xx; xy += o.xy; yy += o.yy;
}

namespace {

// Weighted (w != nullptr) or unweighted sums over one block, positions relative to (rx, ry):
// one pass with eight-lane float accumulators (the block's sums), added in double.
void accumulate_block(double* m, const float* x, const float* y, const float* vx, const float* vy, const float* w,
                      std::size_t len, float rx, float ry) {
  using simd8::F8;
  using simd8::load;
  F8 s0{}, s1{}, s2{}, s3{}, s4{}, s5{}, s6{}, s7{};
  const std::size_t n8 = len / 8 * 8;
  if (w) {
    for (std::size_t i = 0; i < n8; i += 8) {
      const F8 W = load(w + i), dx = load(x + i) - rx, dy = load(y + i) - ry;
      const F8 wdx = W * dx, wdy = W * dy;
      s0 += W;
      s1 += wdx;
      s2 += wdy;
      s3 += W * load(vx + i);
      s4 += W * load(vy + i);
      s5 += wdx * dx;
      s6 += wdx * dy;
      s7 += wdy * dy;
    }
  } else {
    for (std::size_t i = 0; i < n8; i += 8) {
      const F8 dx = load(x + i) - rx, dy = load(y + i) - ry;
      s1 += dx;
      s2 += dy;
      s3 += load(vx + i);
      s4 += load(vy + i);
      s5 += dx * dx;
      s6 += dx * dy;
      s7 += dy * dy;
    }
    s0 = simd8::splat(static_cast<float>(n8 / 8));
  }
  const F8* acc[8] = {&s0, &s1, &s2, &s3, &s4, &s5, &s6, &s7};
  for (int j = 0; j < 8; ++j) {
    const F8& v = *acc[j];
    m[j] += static_cast<double>((v[0] + v[4]) + (v[1] + v[5])) + static_cast<double>((v[2] + v[6]) + (v[3] + v[7]));
  }
  for (std::size_t i = n8; i < len; ++i) {
    const double W = w ? w[i] : 1.0, dx = x[i] - rx, dy = y[i] - ry;
    m[0] += W;
    m[1] += W * dx;
    m[2] += W * dy;
    m[3] += W * vx[i];
    m[4] += W * vy[i];
    m[5] += W * dx * dx;
    m[6] += W * dx * dy;
    m[7] += W * dy * dy;
  }
}

}  // namespace

ParticleFilter::ParticleFilter(const ParticleFilterOptions& options) : options_(options) {
  options_.particles = std::max<std::size_t>(options_.particles, 10);
  if (options_.kld.enabled) {
    options_.kld.min_particles = std::max<std::size_t>(options_.kld.min_particles, 10);
    options_.kld.max_particles = std::min<std::size_t>(std::max(options_.kld.max_particles, options_.kld.min_particles),
                                                       std::numeric_limits<std::uint32_t>::max());
    options_.particles = std::clamp(options_.particles, options_.kld.min_particles, options_.kld.max_particles);
  }
  options_.particles = std::min<std::size_t>(options_.particles, std::numeric_limits<std::uint32_t>::max());
}

void ParticleFilter::reset_weights_uniform() {
  uniform_ = true;
  log_norm_ = 0.0;
  log_w_max_ = 0.0f;
  n_eff_ = static_cast<double>(set_.size());
}

void ParticleFilter::initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) {
  if (!p.allFinite()) return;
  const std::size_t n = options_.particles;
  set_.heading = options_.heading.enabled;
  set_.resize(n);
  origin_ = p;
  // Cholesky factor of the spread; a covariance that is not positive definite falls back
  // to its (absolute) diagonal.
  Eigen::Matrix2d L = Eigen::Matrix2d::Zero();
  const Eigen::LLT<Eigen::Matrix2d> llt(0.5 * (cov_p + cov_p.transpose()));
  if (cov_p.allFinite() && llt.info() == Eigen::Success) {
    L = llt.matrixL();
  } else if (cov_p.allFinite()) {
    L.diagonal() = cov_p.diagonal().cwiseAbs().cwiseSqrt();
  }
  const float l00 = static_cast<float>(L(0, 0)), l10 = static_cast<float>(L(1, 0)),
              l11 = static_cast<float>(L(1, 1)), sv = static_cast<float>(options_.init_speed_sigma);
  const std::uint64_t step = ++step_;
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, c);
    alignas(32) float noise[4 * kBlock];
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(noise, LaneRng::round_up(4 * len, 16));
      const CMapU n1(noise, idx(len)), n2(noise + len, idx(len)), n3(noise + 2 * len, idx(len)),
          n4(noise + 3 * len, idx(len));
      MapF(set_.x.data() + blk, idx(len)) = l00 * n1;
      MapF(set_.y.data() + blk, idx(len)) = l10 * n1 + l11 * n2;
      MapF(set_.vx.data() + blk, idx(len)) = sv * n3;
      MapF(set_.vy.data() + blk, idx(len)) = sv * n4;
    }
  });
  if (set_.gait) draw_gait_prior(++step_);  // the gait calibration starts over too
  if (set_.heading) draw_heading_prior(++step_);
  searching_ = false;
  start_prior();
}

void ParticleFilter::initialize_uniform(const Eigen::AlignedBox2d& region, std::size_t n) {
  if (region.isEmpty() || !region.min().allFinite() || !region.max().allFinite()) return;
  n = std::clamp<std::size_t>(n, 10, std::numeric_limits<std::uint32_t>::max());
  set_.heading = options_.heading.enabled;
  set_.resize(n);
  origin_ = region.center();
  const Eigen::Vector2d size = region.sizes();
  const double sv = options_.init_speed_sigma;
  const std::uint64_t step = ++step_;
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    FastRng rng = FastRng::stream(options_.seed, step, 0x610BA1ull + c);
    for (std::size_t i = b; i < e; ++i) {
      set_.x[i] = static_cast<float>((rng.uniform() - 0.5) * size.x());
      set_.y[i] = static_cast<float>((rng.uniform() - 0.5) * size.y());
      set_.vx[i] = static_cast<float>(sv * rng.normal());
      set_.vy[i] = static_cast<float>(sv * rng.normal());
    }
  });
  if (set_.gait) draw_gait_prior(++step_);
  if (set_.heading) draw_heading_prior(++step_);
  start_search(n);
  start_prior();
}

void ParticleFilter::initialize_around(const std::vector<Eigen::Vector2d>& anchors, const Eigen::Vector2d& w,
                                       double sigma_m, std::size_t n, double yaw_mean, double yaw_sigma) {
  if (anchors.empty() || !w.allFinite() || !(sigma_m >= 0.0)) return;
  n = std::clamp<std::size_t>(n, anchors.size(), std::numeric_limits<std::uint32_t>::max());
  set_.heading = options_.heading.enabled;
  set_.resize(n);
  Eigen::AlignedBox2d box;
  for (const Eigen::Vector2d& a : anchors) box.extend(a);
  origin_ = box.center();
  if (set_.gait) draw_gait_prior(++step_);
  if (set_.heading) draw_heading_prior(++step_, yaw_mean, yaw_sigma);  // first: positions follow each yaw
  const double sv = options_.init_speed_sigma;
  const std::uint64_t step = ++step_;
  const std::size_t h = anchors.size();
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    FastRng rng = FastRng::stream(options_.seed, step, 0xA2C40Full + c);
    for (std::size_t i = b; i < e; ++i) {
      const double yaw = set_.heading ? static_cast<double>(set_.yaw[i]) : 0.0;
      const double cy = std::cos(yaw), sy = std::sin(yaw);
      const Eigen::Vector2d p = anchors[i % h] - Eigen::Vector2d(cy * w.x() - sy * w.y(), sy * w.x() + cy * w.y()) - origin_;
      set_.x[i] = static_cast<float>(p.x() + sigma_m * rng.normal());
      set_.y[i] = static_cast<float>(p.y() + sigma_m * rng.normal());
      set_.vx[i] = static_cast<float>(sv * rng.normal());
      set_.vy[i] = static_cast<float>(sv * rng.normal());
    }
  });
  start_search(n);
  start_prior();
}

void ParticleFilter::start_search(std::size_t n) {
  searching_ = true;
  KldOptions bounds = options_.search_kld;
  bounds.min_particles = options_.particles;
  bounds.max_particles = std::max(n, options_.particles);
  // Particle i of initialize_around belongs to copy i mod h, and initialize_uniform's are
  // independent draws: every prefix is a fair sample of the prior.
  const std::size_t m = kld_prefix_size(set_, bounds);
  if (m < set_.size()) set_.resize(m);
}

void ParticleFilter::start_prior() {
  pending_yaw_var_ = 0.0;
  pending_yaw_decay_ = 1.0;
  reset_weights_uniform();
  averages_.reset();  // a new prior: the old likelihood level says nothing about it
  consecutive_rejections_ = 0;
  initialized_ = true;
  ref_x_ = ref_y_ = 0.0f;
  compute_moments();
}

void ParticleFilter::draw_gait_prior(std::uint64_t step) {
  const float k0 = static_cast<float>(options_.gait.scale0);
  const float s_k = static_cast<float>(options_.gait.scale_sigma0);
  const float s_d = static_cast<float>(options_.gait.heading_offset_sigma0);
  const float k_lo = static_cast<float>(options_.gait.min_scale), k_hi = static_cast<float>(options_.gait.max_scale);
  const float t0 = static_cast<float>(options_.gait.turn_slowdown0);
  const float s_t = static_cast<float>(options_.gait.turn_slowdown_sigma0);
  const float t_lo = static_cast<float>(options_.gait.min_turn_slowdown);
  const float t_hi = static_cast<float>(options_.gait.max_turn_slowdown);
  for_each_particle_chunk(set_.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, 0x6A170000ull + c);
    alignas(32) float noise[3 * kBlock];
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(noise, LaneRng::round_up(3 * len, 16));
      MapF(set_.ks.data() + blk, idx(len)) = (k0 + s_k * CMapU(noise, idx(len))).max(k_lo).min(k_hi);
      MapF(set_.dpsi.data() + blk, idx(len)) = s_d * CMapU(noise + len, idx(len));
      MapF(set_.kturn.data() + blk, idx(len)) = (t0 + s_t * CMapU(noise + 2 * len, idx(len))).max(t_lo).min(t_hi);
    }
  });
}

void ParticleFilter::draw_heading_prior(std::uint64_t step, double mean, double sigma) {
  const float s_e = static_cast<float>(std::isfinite(sigma) ? sigma : options_.heading.sigma0_rad);
  const float m_e = static_cast<float>(std::isfinite(mean) ? mean : 0.0);
  for_each_particle_chunk(set_.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, 0x4EAD0000ull + c);
    alignas(32) float noise[kBlock];
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(noise, LaneRng::round_up(len, 16));
      MapF(set_.yaw.data() + blk, idx(len)) = m_e + s_e * CMapU(noise, idx(len));
    }
  });
}

void ParticleFilter::walk_heading(const MotionInput& u) {
  if (!set_.heading) return;
  // HeadingNoise::propagate, composed with what is pending since the last flush.
  pending_yaw_decay_ *= options_.heading.propagate(pending_yaw_var_, u.dt, u.heading_drift_s, u.heading_bound_rad);
}

void ParticleFilter::flush_heading_walk() {
  if (!set_.heading || !(pending_yaw_var_ > 0.0)) return;
  // Capped at 1 rad^2: beyond that the heading is unknown anyway.
  const float s_e = static_cast<float>(std::sqrt(std::min(pending_yaw_var_, 1.0)));
  const float decay = static_cast<float>(pending_yaw_decay_);
  pending_yaw_var_ = 0.0;
  pending_yaw_decay_ = 1.0;
  const std::uint64_t step = ++step_;
  for_each_particle_chunk(set_.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, 0x4EAD1000ull + c);
    alignas(32) float noise[kBlock];
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(noise, LaneRng::round_up(len, 16));
      MapF E(set_.yaw.data() + blk, idx(len));
      if (decay != 1.0f) E *= decay;
      E += s_e * CMapU(noise, idx(len));
    }
  });
}

ParticleFilter::HeadingEstimate ParticleFilter::heading_estimate() {
  flush_heading_walk();
  HeadingEstimate h;
  if (!initialized_ || !set_.heading) return h;
  const std::size_t n = set_.size();
  std::vector<std::array<double, 3>> part(particle_chunks(n), std::array<double, 3>{});
  const bool weighted = !uniform_;
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    alignas(32) float wbuf[kBlock];
    std::array<double, 3> a{};
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      const CMapF E(set_.yaw.data() + blk, idx(len));
      if (weighted) {
        weights_into(blk, len, wbuf);
        const CMapF W(wbuf, idx(len));
        a[0] += W.sum();
        a[1] += (W * E).sum();
        a[2] += (W * E.square()).sum();
      } else {
        a[0] += static_cast<double>(len);
        a[1] += E.sum();
        a[2] += E.square().sum();
      }
    }
    part[c] = a;
  });
  std::array<double, 3> a{};
  for (const auto& p : part)
    for (int j = 0; j < 3; ++j) a[j] += p[j];
  if (!(a[0] > 0.0)) return h;
  // Offsets stay within a fraction of a radian (the feedback empties them): a linear
  // mean is the circular one.
  h.offset_rad = a[1] / a[0];
  h.sigma_rad = std::sqrt(std::max(0.0, a[2] / a[0] - h.offset_rad * h.offset_rad));
  h.valid = std::isfinite(h.offset_rad) && std::isfinite(h.sigma_rad);
  return h;
}

void ParticleFilter::shift_heading(double delta_rad) {
  if (!set_.heading || !std::isfinite(delta_rad)) return;
  flush_heading_walk();
  const float d = static_cast<float>(delta_rad);
  for_each_particle_chunk(set_.size(), [&](std::size_t, std::size_t b, std::size_t e) {
    MapF(set_.yaw.data() + b, idx(e - b)) -= d;
  });
}

void ParticleFilter::predict_gait(const MotionInput& u) {
  const GaitInput& g = u.gait;
  const std::size_t n = set_.size();
  if (!set_.gait) {
    set_.gait = true;
    set_.resize(n);
    draw_gait_prior(++step_);
  }
  const double dt = u.dt;
  const double vmax = options_.max_speed > 0 ? options_.max_speed : std::numeric_limits<double>::infinity();
  const double speed = std::clamp(g.speed_mps, 0.0, vmax);
  // Per-step noise (SEEDS.md A, S1: l_k, alpha_k each uncertain) spread over the step
  // period as a diffusion: along the walk sigma_l^2 / T, across it (l sigma_alpha)^2 / T.
  const double T = g.step_period_s > 0.05 ? g.step_period_s : 0.55;
  const double l = speed * T;
  const double q0 = std::max(0.0, options_.gait.position_psd);
  const double turn = std::isfinite(g.turn_rate_rps) ? options_.gait.turn_noise * std::abs(g.turn_rate_rps) * T * l : 0.0;
  const double q_turn = turn * turn / T;
  const float s_along =
      static_cast<float>(std::sqrt((g.length_sigma_m * g.length_sigma_m / T + q0 + q_turn) * dt));
  const float s_cross =
      static_cast<float>(std::sqrt((l * l * g.heading_sigma_rad * g.heading_sigma_rad / T + q0 + q_turn) * dt));
  const float c = static_cast<float>(std::cos(g.heading_rad)), s = static_cast<float>(std::sin(g.heading_rad));
  const float s_k = static_cast<float>(options_.gait.scale_walk * std::sqrt(dt));
  const float s_d = static_cast<float>(options_.gait.heading_offset_walk * std::sqrt(dt));
  const float k_lo = static_cast<float>(options_.gait.min_scale), k_hi = static_cast<float>(options_.gait.max_scale);
  const float s_t = static_cast<float>(options_.gait.turn_slowdown_walk * std::sqrt(dt));
  const float t_lo = static_cast<float>(options_.gait.min_turn_slowdown);
  const float t_hi = static_cast<float>(options_.gait.max_turn_slowdown);
  // Turn slowdown per particle: speed = k s - A turn_paid (GaitNoise::turn_slowdown0).
  const float turn_paid = std::isfinite(g.turn_paid_rps) ? static_cast<float>(std::max(0.0, g.turn_paid_rps)) : 0.0f;
  const float f_lo = static_cast<float>(options_.gait.min_turn_factor);
  const float fspeed = static_cast<float>(speed), half_dt = static_cast<float>(0.5 * dt);
  const float ac = s_along * c, as = s_along * s, cc = s_cross * c, cs = s_cross * s;
  walk_heading(u);
  const bool heading = set_.heading;
  const std::uint64_t step = ++step_;
  moments_.assign(particle_chunks(n), Moments{});
  const float rx = ref_x_, ry = ref_y_;
  const bool weighted = !uniform_;
  for_each_particle_chunk(n, [&](std::size_t ch, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, ch);
    alignas(32) float noise[5 * kBlock];
    alignas(32) float wbuf[kBlock];
    double m[8] = {};
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(noise, LaneRng::round_up(5 * len, 16));
      const CMapU n1(noise, idx(len)), n2(noise + len, idx(len)), n3(noise + 2 * len, idx(len)),
          n4(noise + 3 * len, idx(len)), n5(noise + 4 * len, idx(len));
      MapF X(set_.x.data() + blk, idx(len)), Y(set_.y.data() + blk, idx(len));
      MapF VX(set_.vx.data() + blk, idx(len)), VY(set_.vy.data() + blk, idx(len));
      MapF K(set_.ks.data() + blk, idx(len)), D(set_.dpsi.data() + blk, idx(len));
      MapF KT(set_.kturn.data() + blk, idx(len));
      // The calibration states walk slowly (so the fixes can follow a changing gait).
      K = (K + s_k * n1).max(k_lo).min(k_hi);
      D += s_d * n2;
      KT = (KT + s_t * n5).max(t_lo).min(t_hi);
      // Velocity = k * gait speed along AHRS heading + e (the particle's yaw offset) + d
      // (its gait heading offset); trapezoidal position.
      const BlockF ang = heading ? BlockF(D + CMapF(set_.yaw.data() + blk, idx(len))) : BlockF(D);
      const BlockF cd = ang.cos(), sd = ang.sin();
      const BlockF sp = (fspeed * K - KT * turn_paid).max(f_lo * fspeed * K);
      const BlockF vx = sp * (c * cd - s * sd);
      const BlockF vy = sp * (s * cd + c * sd);
      X += half_dt * (VX + vx) + ac * n3 - cs * n4;
      Y += half_dt * (VY + vy) + as * n3 + cc * n4;
      VX = vx;
      VY = vy;
      if (weighted) weights_into(blk, len, wbuf);
      accumulate_block(m, X.data(), Y.data(), VX.data(), VY.data(), weighted ? wbuf : nullptr, len, rx, ry);
    }
    moments_[ch] = Moments{m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7]};
  });
  finish_estimate(moments_);
}

ParticleFilter::GaitEstimate ParticleFilter::gait_estimate() const {
  GaitEstimate g;
  if (!initialized_ || !set_.gait) return g;
  const std::size_t n = set_.size();
  std::vector<std::array<double, 6>> part(particle_chunks(n), std::array<double, 6>{});
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    std::array<double, 6> a{};
    for (std::size_t i = b; i < e; ++i) {
      const double w = weight(i), k = set_.ks[i], d = set_.dpsi[i];
      a[0] += w;
      a[1] += w * k;
      a[2] += w * k * k;
      a[3] += w * d;
      a[4] += w * d * d;
      a[5] += w * set_.kturn[i];
    }
    part[c] = a;
  });
  std::array<double, 6> a{};
  for (const auto& p : part)
    for (int j = 0; j < 6; ++j) a[j] += p[j];
  if (!(a[0] > 0.0)) return g;
  g.scale = a[1] / a[0];
  g.scale_sigma = std::sqrt(std::max(0.0, a[2] / a[0] - g.scale * g.scale));
  g.heading_offset_rad = a[3] / a[0];
  g.heading_offset_sigma = std::sqrt(std::max(0.0, a[4] / a[0] - g.heading_offset_rad * g.heading_offset_rad));
  g.turn_slowdown_m_per_rad = a[5] / a[0];
  g.valid = true;
  return g;
}

void ParticleFilter::widen_gait(double min_scale_sigma, double min_heading_offset_sigma_rad) {
  const GaitEstimate g = gait_estimate();
  if (!g.valid) return;
  // Scaling the deviations keeps each particle's rank and the weighted mean (a widened
  // posterior, not a new prior): sigma' = max(sigma, floor).
  const auto factor = [](double sigma, double floor) {
    return std::isfinite(floor) && floor > sigma ? (sigma > 1e-6 ? floor / sigma : 1.0) : 1.0;
  };
  const float fk = static_cast<float>(factor(g.scale_sigma, min_scale_sigma));
  const float fd = static_cast<float>(factor(g.heading_offset_sigma, min_heading_offset_sigma_rad));
  if (fk == 1.0f && fd == 1.0f) return;
  const float mk = static_cast<float>(g.scale), md = static_cast<float>(g.heading_offset_rad);
  const float k_lo = static_cast<float>(options_.gait.min_scale), k_hi = static_cast<float>(options_.gait.max_scale);
  for_each_particle_chunk(set_.size(), [&](std::size_t, std::size_t b, std::size_t e) {
    MapF K(set_.ks.data() + b, idx(e - b)), D(set_.dpsi.data() + b, idx(e - b));
    K = (mk + fk * (K - mk)).max(k_lo).min(k_hi);
    D = md + fd * (D - md);
  });
}

void ParticleFilter::shift_gait(double dk, double dturn) {
  if (!initialized_ || !set_.gait || !std::isfinite(dk) || !std::isfinite(dturn)) return;
  const float k_lo = static_cast<float>(options_.gait.min_scale), k_hi = static_cast<float>(options_.gait.max_scale);
  const float t_lo = static_cast<float>(options_.gait.min_turn_slowdown);
  const float t_hi = static_cast<float>(options_.gait.max_turn_slowdown);
  const float fk = static_cast<float>(dk), ft = static_cast<float>(dturn);
  for_each_particle_chunk(set_.size(), [&](std::size_t, std::size_t b, std::size_t e) {
    MapF K(set_.ks.data() + b, idx(e - b)), KT(set_.kturn.data() + b, idx(e - b));
    K = (K + fk).max(k_lo).min(k_hi);
    KT = (KT + ft).max(t_lo).min(t_hi);
  });
}

void ParticleFilter::decouple_heading(bool with_gait_offset) {
  const bool gait = with_gait_offset && set_.gait;
  if (!initialized_ || (!set_.heading && !gait)) return;
  const std::size_t n = set_.size();
  FastRng rng = FastRng::stream(options_.seed, ++step_, 0xDEC0ull);
  // Fisher-Yates on both arrays at once.
  for (std::size_t i = n; i > 1; --i) {
    const std::size_t j = static_cast<std::size_t>(rng.uniform() * static_cast<double>(i));
    if (set_.heading) std::swap(set_.yaw[i - 1], set_.yaw[std::min(j, i - 1)]);
    if (gait) std::swap(set_.dpsi[i - 1], set_.dpsi[std::min(j, i - 1)]);
  }
}

void ParticleFilter::predict(const MotionInput& u) {
  if (!initialized_ || !(u.dt > 0.0) || !std::isfinite(u.dt)) return;
  // Every particle moves alike: the origin they are kept relative to does.
  if (u.shift_inW.allFinite()) origin_ += u.shift_inW;
  if (u.has_gait) {
    const GaitInput& g = u.gait;
    if (std::isfinite(g.speed_mps) && std::isfinite(g.heading_rad) && std::isfinite(g.length_sigma_m) &&
        std::isfinite(g.heading_sigma_rad) && std::isfinite(g.step_period_s))
      predict_gait(u);
    return;  // a non-finite gait input predicts nothing (the NaN guard of the other models)
  }
  const double dt = u.dt;
  const Eigen::Vector2d a = (u.has_acc && u.acc_inW.allFinite()) ? u.acc_inW : Eigen::Vector2d::Zero();
  const float sigma_v = static_cast<float>(std::sqrt(std::max(0.0, options_.accel_noise_psd) * dt));
  const float decay =
      static_cast<float>(options_.velocity_tau_s > 0 ? std::exp(-dt / options_.velocity_tau_s) : 1.0);
  const float ax_dt = static_cast<float>(a.x() * dt), ay_dt = static_cast<float>(a.y() * dt);
  const float half_dt = static_cast<float>(0.5 * dt);
  const float vmax = static_cast<float>(options_.max_speed);
  const bool clamp = vmax > 0.0f && std::isfinite(vmax);
  walk_heading(u);
  // The world acceleration turns with the particle's yaw offset (first order: offsets are
  // small, and an acceleration error of e^2 / 2 is below the accelerometer's noise).
  const bool rotate = set_.heading && (ax_dt != 0.0f || ay_dt != 0.0f);
  const std::uint64_t step = ++step_;
  const std::size_t n = set_.size();
  moments_.assign(particle_chunks(n), Moments{});
  const float rx = ref_x_, ry = ref_y_;
  const bool weighted = !uniform_;
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, c);
    alignas(32) float noise[2 * kBlock];
    alignas(32) float wbuf[kBlock];
    double m[8] = {};
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(noise, LaneRng::round_up(2 * len, 16));
      MapF X(set_.x.data() + blk, idx(len)), Y(set_.y.data() + blk, idx(len));
      MapF VX(set_.vx.data() + blk, idx(len)), VY(set_.vy.data() + blk, idx(len));
      // Velocity driven by the measured acceleration plus white noise, decaying towards
      // zero (SEEDS.md B.2, planar inertial integration); trapezoidal position update.
      BlockF vx, vy;
      if (rotate) {
        const CMapF E(set_.yaw.data() + blk, idx(len));
        vx = (VX + ax_dt - ay_dt * E) * decay + sigma_v * CMapU(noise, idx(len));
        vy = (VY + ay_dt + ax_dt * E) * decay + sigma_v * CMapU(noise + len, idx(len));
      } else {
        vx = (VX + ax_dt) * decay + sigma_v * CMapU(noise, idx(len));
        vy = (VY + ay_dt) * decay + sigma_v * CMapU(noise + len, idx(len));
      }
      if (clamp) {
        // k = min(1, vmax / |v|): no select(), which Eigen 3.4 leaves scalar.
        const BlockF k = (vmax * (vx.square() + vy.square()).max(1e-30f).rsqrt()).min(1.0f);
        vx *= k;
        vy *= k;
      }
      X += half_dt * (VX + vx);
      Y += half_dt * (VY + vy);
      VX = vx;
      VY = vy;
      // The estimate's moments while the block is in registers/L1.
      if (weighted) weights_into(blk, len, wbuf);
      accumulate_block(m, X.data(), Y.data(), VX.data(), VY.data(), weighted ? wbuf : nullptr, len, rx, ry);
    }
    moments_[c] = Moments{m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7]};
  });
  finish_estimate(moments_);
}

ParticleFilter::ChunkWeights ParticleFilter::exp_chunk(const float* log_w, std::size_t n, float* lin) {
  ChunkWeights r;
  r.max = CMapF(log_w, idx(n)).maxCoeff();
  if (!(r.max > kNegInf)) {
    r.max = kNegInf;
    std::fill(lin, lin + n, 0.0f);
    return r;
  }
  using simd8::F8;
  const std::size_t n8 = n / 8 * 8;
  F8 s{}, s2{};
  for (std::size_t i = 0; i < n8; i += 8) {
    const F8 e = simd8::exp_nonpositive(simd8::load(log_w + i) - r.max);
    simd8::store(lin + i, e);
    s += e;
    s2 += e * e;
  }
  for (int l = 0; l < 8; ++l) {
    r.sum += s[l];
    r.sum2 += s2[l];
  }
  for (std::size_t i = n8; i < n; ++i) {
    const float d = log_w[i] - r.max;
    const float e = d > kExpFloor ? std::exp(d) : 0.0f;
    lin[i] = e;
    r.sum += e;
    r.sum2 += static_cast<double>(e) * e;
  }
  return r;
}

void ParticleFilter::weights_into(std::size_t i, std::size_t n, float* w) const {
  // The weighing's exp(log_w - chunk max) times exp(chunk max - norm): no exp per particle
  // (a block never straddles a chunk).
  const ChunkWeights& cw = chunk_w_[i / kParticleChunk];
  const float scale = cw.max > kNegInf ? static_cast<float>(std::exp(static_cast<double>(cw.max) - log_norm_)) : 0.0f;
  const float* lin = lin_w_.data() + i;
  const std::size_t n8 = n / 8 * 8;
  for (std::size_t k = 0; k < n8; k += 8) simd8::store(w + k, simd8::load(lin + k) * scale);
  for (std::size_t k = n8; k < n; ++k) w[k] = lin[k] * scale;
}

bool ParticleFilter::commit_weights() {
  float M = kNegInf;
  for (const ChunkWeights& c : chunk_w_next_) M = std::max(M, c.max);
  if (!(M > kNegInf) || !std::isfinite(M)) return false;
  // Global log-sum-exp from the chunk partials, in chunk order.
  double sum = 0.0, sum2 = 0.0;
  for (const ChunkWeights& cw : chunk_w_next_) {
    if (!(cw.max > kNegInf)) continue;
    const double scale = std::exp(static_cast<double>(cw.max) - static_cast<double>(M));
    sum += cw.sum * scale;
    sum2 += cw.sum2 * scale * scale;
  }
  if (!(sum > 0.0) || !std::isfinite(sum) || !(sum2 > 0.0)) return false;
  std::swap(chunk_w_, chunk_w_next_);
  std::swap(lin_w_, lin_w_next_);
  // log of the prior-weighted mean likelihood (the prior was normalised).
  log_norm_ = static_cast<double>(M) + std::log(sum);
  log_w_max_ = M;
  n_eff_ = sum * sum / sum2;
  uniform_ = false;
  estimate_dirty_ = true;
  if (options_.injection.enabled) averages_.update(log_norm_, options_.injection);
  return true;
}

double ParticleFilter::weight(std::size_t i) const {
  if (uniform_) return 1.0 / static_cast<double>(set_.size());
  const double d = static_cast<double>(log_w_[i]) - log_norm_;
  return d > kExpFloor ? std::exp(d) : 0.0;
}

double ParticleFilter::injection_probability() const {
  const InjectionOptions& o = options_.injection;
  if (!o.enabled || o.region.isEmpty()) return 0.0;
  return averages_.injection_probability(o);
}

CorrectionResult ParticleFilter::correct(const PositionMeasurement& m) {
  CorrectionResult r;
  if (!usable(m)) {
    ++rejected_;
    return r;
  }
  if (!initialized_) {
    initialize(m.z, m.R * 4.0);
    r.accepted = r.reinitialized = true;
    return r;
  }
  // Gate against the filter's own spread plus the measurement noise.
  const PlanarEstimate e = estimate();
  const Eigen::Vector2d innov = m.z - e.p;
  const Eigen::Matrix2d S = e.cov_p + m.R;
  r.mahalanobis = std::sqrt(innov.dot(S.ldlt().solve(innov)));
  if (!(r.mahalanobis <= m.gate_sigma)) {
    ++rejected_;
    if (++consecutive_rejections_ >= options_.max_consecutive_rejections) {
      // Lost track (kidnapped, or the prior drifted during a dropout): restart at the fix.
      initialize(m.z, m.R * 4.0);
      ++reinits_;
      r.accepted = r.reinitialized = true;
    }
    return r;
  }
  // SEEDS.md A, S302: w_i ∝ exp(-d_i^T R^-1 d_i / 2) (the patent's scalar R generalised
  // to a 2x2 covariance). The constant -log(2 pi sqrt|R|) does not change the weights;
  // it makes the mean likelihood a density for the injection's averages.
  const Eigen::Matrix2d Ri = m.R.inverse();
  const float a = static_cast<float>(Ri(0, 0)), b = static_cast<float>(Ri(0, 1)), d = static_cast<float>(Ri(1, 1));
  const float c0 = static_cast<float>(-std::log(2.0 * std::numbers::pi * std::sqrt(m.R.determinant())));
  const float zx = static_cast<float>(m.z.x() - origin_.x()), zy = static_cast<float>(m.z.y() - origin_.y());
  const float* x = set_.x.data();
  const float* y = set_.y.data();
  const bool ok = weigh_particles([=](std::size_t i) {
    const float ex = x[i] - zx, ey = y[i] - zy;
    return c0 - 0.5f * (a * ex * ex + 2.0f * b * ex * ey + d * ey * ey);
  });
  if (!ok) {
    initialize(m.z, m.R * 4.0);  // every weight underflowed: recover at the fix
    ++reinits_;
    r.accepted = r.reinitialized = true;
    return r;
  }
  normalize_and_resample();
  consecutive_rejections_ = 0;
  r.accepted = true;
  return r;
}

CorrectionResult ParticleFilter::correct_velocity(const VelocityMeasurement& m) {
  CorrectionResult r;
  if (!initialized_ || !usable(m)) {
    ++rejected_;
    return r;
  }
  // Gate against the particles' velocity spread (a pass: velocity updates are rare).
  const std::size_t n = set_.size();
  const double mvx = estimate().v.x(), mvy = estimate().v.y();
  std::vector<Eigen::Vector3d> part(particle_chunks(n), Eigen::Vector3d::Zero());
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (std::size_t i = b; i < e; ++i) {
      const double w = weight(i), dx = set_.vx[i] - mvx, dy = set_.vy[i] - mvy;
      s += w * Eigen::Vector3d(dx * dx, dx * dy, dy * dy);
    }
    part[c] = s;
  });
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const auto& p : part) s += p;
  Eigen::Matrix2d P;
  P << s(0), s(1), s(1), s(2);
  const Eigen::Vector2d innov = m.v - Eigen::Vector2d(mvx, mvy);
  r.mahalanobis = std::sqrt(innov.dot((P + m.R).ldlt().solve(innov)));
  if (!(r.mahalanobis <= m.gate_sigma)) {
    ++rejected_;
    return r;
  }
  const Eigen::Matrix2d Ri = m.R.inverse();
  const float a = static_cast<float>(Ri(0, 0)), b = static_cast<float>(Ri(0, 1)), d = static_cast<float>(Ri(1, 1));
  const float zx = static_cast<float>(m.v.x()), zy = static_cast<float>(m.v.y());
  const float* vx = set_.vx.data();
  const float* vy = set_.vy.data();
  if (!weigh_particles([=](std::size_t i) {
        const float ex = vx[i] - zx, ey = vy[i] - zy;
        return -0.5f * (a * ex * ex + 2.0f * b * ex * ey + d * ey * ey);
      })) {
    ++rejected_;
    return r;
  }
  normalize_and_resample();
  r.accepted = true;
  return r;
}

bool ParticleFilter::normalize_and_resample() {
  if (!initialized_) return false;
  if (uniform_) return true;  // nothing learnt since the last resampling
  if (options_.resample_every_correction ||
      n_eff_ < options_.resample_threshold * static_cast<double>(set_.size()))
    resample_now();
  return true;
}

void ParticleFilter::resample_now() {
  if (options_.policy == ResamplingPolicy::Genetic) {
    const std::uint64_t step = ++step_;
    // The weighted posterior the step starts from (GeneticOptions::preserve_spread).
    const bool preserve = options_.genetic.preserve_spread && !uniform_;
    const PlanarEstimate before = preserve ? estimate() : PlanarEstimate{};
    const ComponentMoments moments_before = preserve ? component_moments(true) : ComponentMoments{};
    genetic_stats_ = genetic_resample(set_, log_w_, log_w_max_, options_.genetic, options_.seed, step);
    reset_weights_uniform();
    inject_random(step);
    compute_moments();
    if (preserve && before.valid) restore_spread(before, moments_before, step);
  } else {
    resample_copy();
  }
  ++resamples_;
}

std::vector<float*> ParticleFilter::spread_components() {
  std::vector<float*> c{set_.vx.data(), set_.vy.data()};
  if (set_.gait) c.insert(c.end(), {set_.ks.data(), set_.dpsi.data(), set_.kturn.data()});
  if (set_.heading) c.push_back(set_.yaw.data());
  return c;
}

ParticleFilter::ComponentMoments ParticleFilter::component_moments(bool weighted) {
  const std::vector<float*> comps = spread_components();
  const std::size_t n = set_.size(), k = comps.size();
  ComponentMoments out{std::vector<double>(k, 0.0), std::vector<double>(k, 0.0)};
  if (n == 0) return out;
  // Per chunk: sum w, sum w d, sum w d^2 with d about particle 0's value (no cancellation
  // at float precision); the chunks summed in order (deterministic). Blocks of kBlock with
  // the weighing's own weights (weights_into: no exp per particle).
  const std::size_t stride = 1 + 2 * k;
  std::vector<double> part(particle_chunks(n) * stride, 0.0);
  std::vector<float> ref(k);
  for (std::size_t j = 0; j < k; ++j) ref[j] = comps[j][0];
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    double* acc = part.data() + c * stride;
    alignas(32) float wbuf[kBlock];
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      if (weighted) {
        weights_into(blk, len, wbuf);
      } else {
        std::fill_n(wbuf, len, 1.0f);
      }
      float sw = 0.0f;
      for (std::size_t q = 0; q < len; ++q) sw += wbuf[q];
      acc[0] += sw;
      for (std::size_t j = 0; j < k; ++j) {
        const float* v = comps[j] + blk;
        const float r = ref[j];
        float s1 = 0.0f, s2 = 0.0f;
        for (std::size_t q = 0; q < len; ++q) {
          const float d = v[q] - r;
          s1 += wbuf[q] * d;
          s2 += wbuf[q] * d * d;
        }
        acc[1 + 2 * j] += s1;
        acc[2 + 2 * j] += s2;
      }
    }
  });
  std::vector<double> sum(stride, 0.0);
  for (std::size_t c = 0; c < particle_chunks(n); ++c)
    for (std::size_t j = 0; j < stride; ++j) sum[j] += part[c * stride + j];
  if (!(sum[0] > 0.0)) return out;
  for (std::size_t j = 0; j < k; ++j) {
    const double m = sum[1 + 2 * j] / sum[0];
    out.mean[j] = static_cast<double>(ref[j]) + m;
    out.var[j] = std::max(0.0, sum[2 + 2 * j] / sum[0] - m * m);
  }
  return out;
}

void ParticleFilter::restore_spread(const PlanarEstimate& before, const ComponentMoments& moments_before,
                                    std::uint64_t step) {
  const Eigen::Matrix2d& cov_before = before.cov_p;
  if (!estimate_.valid || !cov_before.allFinite() || !before.p.allFinite()) return;
  // Mean: the decayed particles keep 1 - alpha of their old place, so the equal-weight set
  // sits between the prior and the weighted posterior (the filter lags its measurements):
  // every particle moves by the weighted mean before less the mean now.
  const Eigen::Vector2d shift = before.p - estimate_.p;
  const float sx = static_cast<float>(shift.x()), sy = static_cast<float>(shift.y());
  // Position spread: Q = cov_before - cov_now, negative eigenvalues dropped; x += L n, L L^T = Q.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov_before - estimate_.cov_p);
  if (es.info() != Eigen::Success) return;
  const Eigen::Vector2d lambda = es.eigenvalues().cwiseMax(0.0);
  const Eigen::Matrix2d L = es.eigenvectors() * lambda.cwiseSqrt().asDiagonal();
  const float l00 = static_cast<float>(L(0, 0)), l01 = static_cast<float>(L(0, 1));
  const float l10 = static_cast<float>(L(1, 0)), l11 = static_cast<float>(L(1, 1));
  // The other components, one by one: the mean shift and the standard deviation each lost.
  const std::vector<float*> comps = spread_components();
  const ComponentMoments now = component_moments(false);
  std::vector<float*> jitter;
  std::vector<float> lost, moved;
  for (std::size_t j = 0; j < comps.size() && j < moments_before.var.size(); ++j) {
    const double d = moments_before.var[j] - now.var[j];
    const double m = moments_before.mean[j] - now.mean[j];
    jitter.push_back(comps[j]);
    lost.push_back(d > 0.0 && std::isfinite(d) ? static_cast<float>(std::sqrt(d)) : 0.0f);
    moved.push_back(std::isfinite(m) ? static_cast<float>(m) : 0.0f);
  }
  const std::size_t nc = 2 + jitter.size();  // normals per particle
  for_each_particle_chunk(set_.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
    // Its own streams (0x5B5B5 + chunk), apart from the propagation's and the genetic step's.
    LaneRng rng(options_.seed, step, 0x5B5B5ull + c);
    std::vector<float> nrm(LaneRng::round_up(nc * kBlock, 16));
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      rng.fill_normal(nrm.data(), nrm.size());
      float* x = set_.x.data() + blk;
      float* y = set_.y.data() + blk;
      const float* n0 = nrm.data();
      const float* n1 = nrm.data() + kBlock;
      for (std::size_t q = 0; q < len; ++q) {
        x[q] += sx + l00 * n0[q] + l01 * n1[q];
        y[q] += sy + l10 * n0[q] + l11 * n1[q];
      }
      for (std::size_t j = 0; j < jitter.size(); ++j) {
        float* v = jitter[j] + blk;
        const float* nj = nrm.data() + (2 + j) * kBlock;
        const float sj = lost[j], mj = moved[j];
        for (std::size_t q = 0; q < len; ++q) v[q] += mj + sj * nj[q];
      }
    }
  });
  compute_moments();
}

void ParticleFilter::inject_random(std::uint64_t step) {
  const double p = injection_probability();
  if (!(p > 0.0)) return;
  const Eigen::AlignedBox2d& box = options_.injection.region;
  const Eigen::Vector2d lo = box.min() - origin_, size = box.sizes();
  const double sv = options_.init_speed_sigma;
  const std::size_t n = set_.size();
  std::vector<std::uint64_t> count(particle_chunks(n), 0);
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    FastRng rng = FastRng::stream(options_.seed, step, 0x1000000ull + c);
    for (std::size_t i = b; i < e; ++i) {
      if (rng.uniform() >= p) continue;
      set_.x[i] = static_cast<float>(lo.x() + rng.uniform() * size.x());
      set_.y[i] = static_cast<float>(lo.y() + rng.uniform() * size.y());
      set_.vx[i] = static_cast<float>(sv * rng.normal());
      set_.vy[i] = static_cast<float>(sv * rng.normal());
      if (set_.gait) {
        set_.ks[i] = static_cast<float>(options_.gait.scale0);  // the uncalibrated gait
        set_.dpsi[i] = 0.0f;
        set_.kturn[i] = static_cast<float>(options_.gait.turn_slowdown0);
      }
      if (set_.heading) set_.yaw[i] = 0.0f;  // the AHRS's yaw
      ++count[c];
    }
  });
  std::uint64_t total = 0;
  for (auto k : count) total += k;
  injected_ += total;
  if (total > 0) averages_.reset();
}

void ParticleFilter::resample_copy() {
  const std::uint64_t step = ++step_;
  const std::size_t n = set_.size();
  std::size_t m = n;
  // Systematic without KLD-sampling: the ancestors and the gather in one pass.
  const bool fused = options_.scheme == ResamplingScheme::Systematic && !options_.kld.enabled;
  const auto draw = [&](std::size_t children) {
    if (options_.scheme == ResamplingScheme::Systematic) {
      systematic_ancestors(children, step);
      return;
    }
    std::vector<double> w(n);
    for_each_particle_chunk(n, [&](std::size_t, std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) w[i] = weight(i);
    });
    resample(options_.scheme, w, FastRng::stream(options_.seed, step, 0xA11CEull).next(), ancestors_, children);
  };
  // A global search ends when one hypothesis is left: 0.5 m, a tenth of a reuse distance,
  // where a second copy's cluster can no longer hide in it. Until then it keeps the size
  // KLD-sampling gave its start (start_search). Resizing it by the bins of each resampled
  // set too (Fox's full scheme) was tried on tuning seed 1 (floorplan, 200 s, kidnap at
  // 100 s): the set shrank to 2000-5000 while two copies still competed, and the restart
  // after the kidnap converged on a wrong copy (caught by the gate 0.3 s later), which the
  // fixed size never did; so the size is fixed once the search has started.
  if (localising()) {
    constexpr double kConvergedSigmaM = 0.5;
    if (!search_hold_ && estimate().cov_p.trace() < 2.0 * kConvergedSigmaM * kConvergedSigmaM) {
      m = options_.particles;
      searching_ = false;
    }
    if (fused) {
      resample_systematic(m, step);
    } else {
      draw(m);
      gather(step);
    }
    return;
  }
  if (fused) return resample_systematic(n, step);
  draw(n);
  if (options_.kld.enabled) {
    // KLD-sampling: bins occupied by the drawn ancestors decide the next set's size.
    m = kld_particle_count(count_occupied_bins(set_, ancestors_, options_.kld), options_.kld);
    if (m != n) draw(m);
  }
  gather(step);
}

std::vector<double> ParticleFilter::systematic_bounds(std::size_t m, std::uint64_t step, double& u) const {
  // Chunk boundaries of the scaled cumulative weight, from the chunk sums.
  const std::size_t chunks = particle_chunks(set_.size());
  std::vector<double> C(chunks + 1, 0.0);
  const double dm = static_cast<double>(m);
  for (std::size_t c = 0; c < chunks; ++c) {
    const ChunkWeights& cw = chunk_w_[c];
    const double mass = cw.max > kNegInf ? cw.sum * std::exp(static_cast<double>(cw.max) - log_norm_) : 0.0;
    C[c + 1] = C[c] + dm * mass;
  }
  C[chunks] = dm;
  u = FastRng::stream(options_.seed, step, 0xA11CEull).uniform();
  return C;
}

std::pair<std::size_t, std::size_t> ParticleFilter::place_children(const std::vector<double>& C, double u,
                                                                    std::size_t m, std::size_t c, std::size_t b,
                                                                    std::size_t e) {
  // Systematic resampling over chunks: child k copies the particle whose scaled
  // cumulative weight interval holds k + u. Each chunk places exactly its children
  // [ceil(C[c] - u), ceil(C[c+1] - u)), so rounding inside a chunk can never lose or
  // duplicate a child.
  const std::size_t chunks = C.size() - 1;
  const double dm = static_cast<double>(m);
  const auto first_child = [&](double cum) {
    return static_cast<std::size_t>(std::clamp(std::ceil(cum - u), 0.0, dm));
  };
  const std::size_t kb = first_child(C[c]);
  const std::size_t ke = c + 1 == chunks ? m : first_child(C[c + 1]);
  if (kb >= ke) return {kb, kb};
  // Branch-free placement: particle i's first child is ceil(cum_{i-1} - u); mark that
  // child with i + 1 (a later particle with the same first child — the earlier one
  // has none — overwrites it), then a running maximum gives every child the last
  // particle marked at or before it. Chunk c's children [kb, ke) sit at kb + c in
  // ancestors_ (sized m + chunks), so each chunk has a slot of its own past its last
  // child: the sink that dead particles and rounding overshoots mark, without a branch.
  std::uint32_t* anc = ancestors_.data() + kb + c;
  const std::size_t count = ke - kb;
  std::fill(anc, anc + count + 1, 0u);
  using simd8::F8;
  using simd8::I8;
  const F8 fcount = simd8::splat(static_cast<float>(count));
  const I8 icount = I8{} + static_cast<std::int32_t>(count);
  // Weights in children: the weighing's exp(log_w - chunk max) times m exp(chunk max - norm).
  const ChunkWeights& cw = chunk_w_[c];
  const double dscale = cw.max > kNegInf ? dm * std::exp(static_cast<double>(cw.max) - log_norm_) : 0.0;
  const float scale = static_cast<float>(dscale);
  const float* lin = lin_w_.data();
  double base = C[c] - u - static_cast<double>(kb);  // in children, relative to kb: (-1, 0]
  const std::size_t e8 = b + (e - b) / 8 * 8;
  std::size_t i = b;
  for (; i < e8; i += 8) {
    const F8 w = simd8::load(lin + i) * scale;
    // Inclusive prefix sum across the 8 lanes (shift-and-add), then exclusive.
    F8 p = w;
    p += simd8::shift_up<1>(p);
    p += simd8::shift_up<2>(p);
    p += simd8::shift_up<4>(p);
    const F8 before = (p - w) + static_cast<float>(base);
    // ceil(before) for before > -1.
    I8 first = __builtin_convertvector(before, I8);
    first = __builtin_convertvector(first, F8) < before ? first + 1 : first;
    // A dead particle, or one past the chunk's last child, marks the sink (slot count).
    const I8 valid = (w > 0.0f) & (__builtin_convertvector(first, F8) < fcount);
    first = first < 0 ? I8{} : first;
    const I8 slot = valid ? first : icount;
    alignas(32) std::int32_t sl[8];
    std::memcpy(sl, &slot, sizeof sl);
    for (int l = 0; l < 8; ++l) anc[sl[l]] = static_cast<std::uint32_t>(i + static_cast<std::size_t>(l) + 1);
    base += static_cast<double>(p[7]);
  }
  for (; i < e; ++i) {
    const double w = static_cast<double>(lin[i]) * dscale;
    const double first = std::ceil(base);
    if (w > 0.0 && first < static_cast<double>(count))
      anc[static_cast<std::size_t>(std::max(first, 0.0))] = static_cast<std::uint32_t>(i + 1);
    base += w;
  }
  // Running maximum (eight at a time: in-register prefix max, then the carry), minus 1.
  using simd8::U8;
  U8 carry = U8{} + static_cast<std::uint32_t>(b + 1);  // never unset, even if anc[0] were
  const std::size_t c8 = count / 8 * 8;
  std::size_t k = 0;
  for (; k < c8; k += 8) {
    U8 v;
    std::memcpy(&v, anc + k, sizeof v);
    const auto vmax = [](U8 a, U8 b2) { return a > b2 ? a : b2; };
    v = vmax(v, simd8::shift_up<1>(v));
    v = vmax(v, simd8::shift_up<2>(v));
    v = vmax(v, simd8::shift_up<4>(v));
    v = vmax(v, carry);
    carry = U8{} + v[7];
    const U8 out = v - 1u;
    std::memcpy(anc + k, &out, sizeof out);
  }
  std::uint32_t last = carry[0];
  for (; k < count; ++k) {
    last = std::max(last, anc[k]);
    anc[k] = last - 1;
  }
  return {kb, ke};
}

void ParticleFilter::systematic_ancestors(std::size_t m, std::uint64_t step) {
  double u = 0.0;
  const std::vector<double> C = systematic_bounds(m, step, u);
  const std::size_t chunks = particle_chunks(set_.size());
  ancestors_.resize(m + chunks);
  std::vector<std::pair<std::size_t, std::size_t>> ranges(chunks);
  for_each_particle_chunk(set_.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
    ranges[c] = place_children(C, u, m, c, b, e);
  });
  // Close the sink slots: chunk c's children move down by c (in chunk order: dst < src).
  for (std::size_t c = 1; c < chunks; ++c)
    if (ranges[c].second > ranges[c].first)
      std::memmove(ancestors_.data() + ranges[c].first, ancestors_.data() + ranges[c].first + c,
                   (ranges[c].second - ranges[c].first) * sizeof(std::uint32_t));
  ancestors_.resize(m);
}

void ParticleFilter::gather_block(const std::uint32_t* anc, std::size_t k0, std::size_t len, LaneRng& rng,
                                  double* mom) {
  // Copies children [k0, k0 + len) (len <= kBlock) from their ancestors anc[0, len) into
  // scratch_, roughens them and adds their moments.
  alignas(32) float noise[2 * kBlock];
  float* sx = scratch_.x.data() + k0;
  float* sy = scratch_.y.data() + k0;
  float* svx = scratch_.vx.data() + k0;
  float* svy = scratch_.vy.data() + k0;
  const float* px = set_.x.data();
  const float* py = set_.y.data();
  const float* pvx = set_.vx.data();
  const float* pvy = set_.vy.data();
  const bool yaw_with = set_.heading && !set_.gait;  // the common case: one loop for all five
  if (yaw_with) {
    const float* pe = set_.yaw.data();
    float* se = scratch_.yaw.data() + k0;
    for (std::size_t k = 0; k < len; ++k) {
      const std::uint32_t i = anc[k];
      sx[k] = px[i];
      sy[k] = py[i];
      svx[k] = pvx[i];
      svy[k] = pvy[i];
      se[k] = pe[i];
    }
  } else {
    for (std::size_t k = 0; k < len; ++k) {
      const std::uint32_t i = anc[k];
      sx[k] = px[i];
      sy[k] = py[i];
      svx[k] = pvx[i];
      svy[k] = pvy[i];
    }
  }
  if (set_.gait) {
    float* sk = scratch_.ks.data() + k0;
    float* sd = scratch_.dpsi.data() + k0;
    float* st = scratch_.kturn.data() + k0;
    for (std::size_t k = 0; k < len; ++k) {
      const std::uint32_t i = anc[k];
      sk[k] = set_.ks[i];
      sd[k] = set_.dpsi[i];
      st[k] = set_.kturn[i];
    }
  }
  if (set_.heading && !yaw_with) {
    float* se = scratch_.yaw.data() + k0;
    for (std::size_t k = 0; k < len; ++k) se[k] = set_.yaw[anc[k]];
  }
  const float jitter = static_cast<float>(options_.roughening_m);
  if (jitter > 0.0f) {
    // Roughening (Gordon et al. 1993) against copies collapsing onto one point; a
    // triangular kernel with the same sigma (the shape is immaterial at mm scale).
    rng.fill_triangular(noise, LaneRng::round_up(2 * len, 8));
    Eigen::Map<Eigen::ArrayXf>(sx, idx(len)) += jitter * CMapU(noise, idx(len));
    Eigen::Map<Eigen::ArrayXf>(sy, idx(len)) += jitter * CMapU(noise + len, idx(len));
  }
  accumulate_block(mom, sx, sy, svx, svy, nullptr, len, ref_x_, ref_y_);
}

void ParticleFilter::prepare_scratch(std::size_t m) {
  scratch_.gait = set_.gait;
  scratch_.heading = set_.heading;
  scratch_.resize(m);
}

void ParticleFilter::finish_resample(std::uint64_t step) {
  std::swap(set_.x, scratch_.x);
  std::swap(set_.y, scratch_.y);
  std::swap(set_.vx, scratch_.vx);
  std::swap(set_.vy, scratch_.vy);
  std::swap(set_.ks, scratch_.ks);
  std::swap(set_.dpsi, scratch_.dpsi);
  std::swap(set_.kturn, scratch_.kturn);
  std::swap(set_.yaw, scratch_.yaw);
  reset_weights_uniform();
  if (injection_probability() > 0.0) {
    inject_random(step);  // rare: recompute the moments rather than fold it in above
    compute_moments();
  } else {
    finish_estimate(moments_);
  }
}

void ParticleFilter::gather(std::uint64_t step) {
  // Children in fixed 4096-child chunks, each with the random stream of its index.
  const std::size_t m = ancestors_.size();
  prepare_scratch(m);
  moments_.assign(particle_chunks(m), Moments{});
  for_each_particle_chunk(m, [&](std::size_t c, std::size_t b, std::size_t e) {
    LaneRng rng(options_.seed, step, c);
    double mom[8] = {};
    for (std::size_t blk = b; blk < e; blk += kBlock)
      gather_block(ancestors_.data() + blk, blk, std::min(kBlock, e - blk), rng, mom);
    moments_[c] = Moments{mom[0], mom[1], mom[2], mom[3], mom[4], mom[5], mom[6], mom[7]};
  });
  finish_resample(step);
}

void ParticleFilter::resample_systematic(std::size_t m, std::uint64_t step) {
  // Systematic resampling and the gather in one pass per parent chunk: the chunk's
  // ancestors are still in L1/L2 when its children are copied, and its particles are
  // read while hot (one parallel pass less, no ancestor array through memory). The
  // children of parent chunk c are copied in pieces of 4096 children, each with the
  // random stream keyed by (step, c, piece), so the numbers do not depend on the thread
  // count; a chunk with many children (a peaked likelihood) spreads its pieces over the
  // threads.
  double u = 0.0;
  const std::vector<double> C = systematic_bounds(m, step, u);
  const std::size_t n = set_.size();
  ancestors_.resize(m + particle_chunks(n));  // chunk c's children at kb + c (place_children)
  prepare_scratch(m);
  moments_.assign(particle_chunks(n), Moments{});
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    // Plain variables, not a structured binding: clang 14 (the sanitizer builds) cannot
    // capture bindings in the lambda below.
    const auto children = place_children(C, u, m, c, b, e);
    const std::size_t kb = children.first, ke = children.second;
    const std::size_t pieces = (ke - kb + kParticleChunk - 1) / kParticleChunk;
    const auto piece = [&](std::size_t p, double* mom) {
      LaneRng rng(options_.seed, step, (static_cast<std::uint64_t>(p) << 32) | c);
      const std::size_t pb = kb + p * kParticleChunk, pe = std::min(ke, pb + kParticleChunk);
      for (std::size_t blk = pb; blk < pe; blk += kBlock)
        gather_block(ancestors_.data() + blk + c, blk, std::min(kBlock, pe - blk), rng, mom);
    };
    Moments total;
    if (pieces <= 2) {
      for (std::size_t p = 0; p < pieces; ++p) {
        double mom[8] = {};
        piece(p, mom);
        total.add(Moments{mom[0], mom[1], mom[2], mom[3], mom[4], mom[5], mom[6], mom[7]});
      }
    } else {
      std::vector<Moments> part(pieces);
      tbb::parallel_for(std::size_t{0}, pieces, [&](std::size_t p) {
        double mom[8] = {};
        piece(p, mom);
        part[p] = Moments{mom[0], mom[1], mom[2], mom[3], mom[4], mom[5], mom[6], mom[7]};
      });
      for (const Moments& mp : part) total.add(mp);
    }
    moments_[c] = total;
  });
  finish_resample(step);
}

void ParticleFilter::compute_moments() const {
  const std::size_t n = set_.size();
  moments_.assign(particle_chunks(n), Moments{});
  const float rx = ref_x_, ry = ref_y_;
  const bool weighted = !uniform_;
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    alignas(32) float wbuf[kBlock];
    double m[8] = {};
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      if (weighted) weights_into(blk, len, wbuf);
      accumulate_block(m, set_.x.data() + blk, set_.y.data() + blk, set_.vx.data() + blk, set_.vy.data() + blk,
                       weighted ? wbuf : nullptr, len, rx, ry);
    }
    moments_[c] = Moments{m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7]};
  });
  finish_estimate(moments_);
}

void ParticleFilter::finish_estimate(const std::vector<Moments>& per_chunk) const {
  // Weighted mean and covariance (SEEDS.md A, S303: A'_k = sum_i w_i A_i), chunk partials
  // summed in chunk order (deterministic).
  Moments s;
  for (const Moments& m : per_chunk) s.add(m);
  estimate_dirty_ = false;
  if (!(s.w > 0.0) || !std::isfinite(s.w)) {
    estimate_.valid = false;
    return;
  }
  const double mx = s.x / s.w, my = s.y / s.w;
  Eigen::Matrix2d cov;
  cov << s.xx / s.w - mx * mx, s.xy / s.w - mx * my, s.xy / s.w - mx * my, s.yy / s.w - my * my;
  cov.diagonal() = cov.diagonal().cwiseMax(0.0);
  cov += Eigen::Matrix2d::Identity() * 1e-12;
  PlanarEstimate e;
  e.p = origin_ + Eigen::Vector2d(ref_x_ + mx, ref_y_ + my);
  e.v = {s.vx / s.w, s.vy / s.w};
  e.cov_p = cov;
  e.n_eff = n_eff_;
  e.valid = e.p.allFinite() && e.v.allFinite() && cov.allFinite();
  if (!e.valid) {
    estimate_.valid = false;
    return;
  }
  estimate_ = e;
  // Next passes take their moments about the current mean.
  ref_x_ = static_cast<float>(e.p.x() - origin_.x());
  ref_y_ = static_cast<float>(e.p.y() - origin_.y());
}

PlanarEstimate ParticleFilter::estimate() const {
  if (initialized_ && estimate_dirty_) compute_moments();
  PlanarEstimate e = estimate_;
  e.n_eff = n_eff_;
  return e;
}

}  // namespace luxloc
