#include "core/filter/particle_filter.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/filter/fast_rng.hpp"

namespace luxloc {
namespace {

constexpr std::size_t kChunk = 4096;  // fixed chunking -> deterministic random streams

template <typename F>
void for_each_chunk(std::size_t n, F&& f) {
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  if (chunks <= 1) {
    if (n) f(std::size_t{0}, std::size_t{0}, n);
    return;
  }
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    f(c, c * kChunk, std::min(n, (c + 1) * kChunk));
  });
}

}  // namespace

ParticleFilter::ParticleFilter(const ParticleFilterOptions& options) : options_(options) {
  options_.particles = std::max<std::size_t>(options_.particles, 10);
}

void ParticleFilter::initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) {
  const std::size_t n = options_.particles;
  set_.resize(n);
  const Eigen::Matrix2d L = cov_p.llt().matrixL();
  const std::uint64_t step = ++step_;
  for_each_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    FastRng rng = FastRng::stream(options_.seed, step, c);
    for (std::size_t i = b; i < e; ++i) {
      const Eigen::Vector2d d = L * Eigen::Vector2d(rng.normal(), rng.normal());
      set_.x[i] = p.x() + d.x();
      set_.y[i] = p.y() + d.y();
      set_.vx[i] = options_.init_speed_sigma * rng.normal();
      set_.vy[i] = options_.init_speed_sigma * rng.normal();
      set_.log_w[i] = 0.0;
      set_.w[i] = 1.0 / static_cast<double>(n);
    }
  });
  n_eff_ = static_cast<double>(n);
  consecutive_rejections_ = 0;
  initialized_ = true;
  update_estimate();
}

void ParticleFilter::predict(const MotionInput& u) {
  if (!initialized_ || !(u.dt > 0.0) || !std::isfinite(u.dt)) return;
  const double dt = u.dt;
  const Eigen::Vector2d a = (u.has_acc && u.acc_inW.allFinite()) ? u.acc_inW : Eigen::Vector2d::Zero();
  const double sigma_v = std::sqrt(options_.accel_noise_psd * dt);
  const double decay = options_.velocity_tau_s > 0 ? std::exp(-dt / options_.velocity_tau_s) : 1.0;
  const double vmax = options_.max_speed;
  const std::uint64_t step = ++step_;
  for_each_chunk(set_.size(), [&](std::size_t c, std::size_t b, std::size_t e) {
    FastRng rng = FastRng::stream(options_.seed, step, c);
    for (std::size_t i = b; i < e; ++i) {
      // Constant velocity driven by the measured acceleration plus white noise
      // (SEEDS.md B.2, planar inertial integration), trapezoidal position update.
      const double vx0 = set_.vx[i], vy0 = set_.vy[i];
      double vx = (vx0 + a.x() * dt) * decay + sigma_v * rng.normal();
      double vy = (vy0 + a.y() * dt) * decay + sigma_v * rng.normal();
      const double s2 = vx * vx + vy * vy;
      if (s2 > vmax * vmax) {
        const double k = vmax / std::sqrt(s2);
        vx *= k;
        vy *= k;
      }
      set_.x[i] += 0.5 * (vx0 + vx) * dt;
      set_.y[i] += 0.5 * (vy0 + vy) * dt;
      set_.vx[i] = vx;
      set_.vy[i] = vy;
    }
  });
  update_estimate();
}

CorrectionResult ParticleFilter::correct(const PositionMeasurement& m) {
  CorrectionResult r;
  if (!m.z.allFinite() || !m.R.allFinite() || m.R.determinant() <= 0.0) {
    ++rejected_;
    return r;
  }
  if (!initialized_) {
    initialize(m.z, m.R * 4.0);
    r.accepted = r.reinitialized = true;
    return r;
  }
  // Gate against the filter's own spread plus the measurement noise.
  const Eigen::Vector2d innov = m.z - estimate_.p;
  const Eigen::Matrix2d S = estimate_.cov_p + m.R;
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
  // to a 2x2 covariance); the constant 1/sqrt(2 pi R) cancels in the normalisation.
  const Eigen::Matrix2d Ri = m.R.inverse();
  const double a = Ri(0, 0), b = Ri(0, 1), d = Ri(1, 1);
  const double zx = m.z.x(), zy = m.z.y();
  const bool ok = weigh([=](double x, double y) {
    const double ex = x - zx, ey = y - zy;
    return -0.5 * (a * ex * ex + 2.0 * b * ex * ey + d * ey * ey);
  });
  if (!ok || !normalize_and_resample()) {
    initialize(m.z, m.R * 4.0);  // every weight underflowed: recover at the fix
    ++reinits_;
    r.accepted = r.reinitialized = true;
    return r;
  }
  consecutive_rejections_ = 0;
  r.accepted = true;
  return r;
}

bool ParticleFilter::normalize_and_resample() {
  const std::size_t n = set_.size();
  const double max_lw = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 8192), -std::numeric_limits<double>::infinity(),
      [&](const tbb::blocked_range<std::size_t>& r, double m) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) m = std::max(m, set_.log_w[i]);
        return m;
      },
      [](double x, double y) { return std::max(x, y); });
  if (!std::isfinite(max_lw)) return false;
  // log-sum-exp normalisation; sum of w and of w^2 in one reduction.
  using Sums = std::pair<double, double>;
  const Sums sums = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 8192), Sums{0.0, 0.0},
      [&](const tbb::blocked_range<std::size_t>& r, Sums s) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const double w = std::exp(set_.log_w[i] - max_lw);
          set_.w[i] = w;
          s.first += w;
          s.second += w * w;
        }
        return s;
      },
      [](Sums x, Sums y) { return Sums{x.first + y.first, x.second + y.second}; });
  if (!(sums.first > 0.0) || !std::isfinite(sums.first)) return false;
  const double inv = 1.0 / sums.first;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16384), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      set_.w[i] *= inv;
      set_.log_w[i] = std::log(set_.w[i]);  // keep log weights bounded
    }
  });
  n_eff_ = (sums.first * sums.first) / sums.second;  // 1 / sum(w_norm^2)
  update_estimate();
  if (options_.resample_every_correction || n_eff_ < options_.resample_threshold * static_cast<double>(n))
    resample_now();
  return true;
}

void ParticleFilter::resample_now() {
  const std::size_t n = set_.size();
  const std::uint64_t step = ++step_;
  resample(options_.scheme, set_.w, FastRng::stream(options_.seed, step, 0xA11CEull).next(), ancestors_);
  scratch_.resize(n);
  const double inv_n = 1.0 / static_cast<double>(n);
  const double log_inv_n = std::log(inv_n);
  const double jitter = options_.roughening_m;
  for_each_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    FastRng rng = FastRng::stream(options_.seed, step, c + 1);
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t k = ancestors_[i];
      scratch_.x[i] = set_.x[k] + (jitter > 0 ? jitter * rng.normal() : 0.0);
      scratch_.y[i] = set_.y[k] + (jitter > 0 ? jitter * rng.normal() : 0.0);
      scratch_.vx[i] = set_.vx[k];
      scratch_.vy[i] = set_.vy[k];
      // Weights reset after resampling (unlike MRPT 2.5.8, see FIELD_NOTES.md).
      scratch_.log_w[i] = log_inv_n;
      scratch_.w[i] = inv_n;
    }
  });
  std::swap(set_, scratch_);
  n_eff_ = static_cast<double>(n);
  ++resamples_;
  update_estimate();
}

void ParticleFilter::update_estimate() {
  // Weighted mean and covariance (SEEDS.md A, S303: A'_k = sum_i w_i A_i).
  const std::size_t n = set_.size();
  struct Acc {
    double w = 0, x = 0, y = 0, vx = 0, vy = 0, xx = 0, xy = 0, yy = 0;
  };
  // Relative to a reference particle for numerical stability of the second moments.
  const double x0 = set_.x[0], y0 = set_.y[0];
  const Acc s = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 8192), Acc{},
      [&](const tbb::blocked_range<std::size_t>& r, Acc a) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const double w = set_.w[i];
          const double dx = set_.x[i] - x0, dy = set_.y[i] - y0;
          a.w += w;
          a.x += w * dx;
          a.y += w * dy;
          a.vx += w * set_.vx[i];
          a.vy += w * set_.vy[i];
          a.xx += w * dx * dx;
          a.xy += w * dx * dy;
          a.yy += w * dy * dy;
        }
        return a;
      },
      [](Acc a, const Acc& b) {
        a.w += b.w; a.x += b.x; a.y += b.y; a.vx += b.vx; a.vy += b.vy;
        a.xx += b.xx; a.xy += b.xy; a.yy += b.yy;
        return a;
      });
  if (!(s.w > 0.0) || !std::isfinite(s.w)) {
    estimate_.valid = false;
    return;
  }
  const double mx = s.x / s.w, my = s.y / s.w;
  estimate_.p = {x0 + mx, y0 + my};
  estimate_.v = {s.vx / s.w, s.vy / s.w};
  estimate_.cov_p << s.xx / s.w - mx * mx, s.xy / s.w - mx * my, s.xy / s.w - mx * my, s.yy / s.w - my * my;
  estimate_.cov_p += Eigen::Matrix2d::Identity() * 1e-12;
  estimate_.n_eff = n_eff_;
  estimate_.valid = estimate_.p.allFinite();
}

}  // namespace luxloc
