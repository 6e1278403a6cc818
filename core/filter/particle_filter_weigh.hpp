#pragma once
// ParticleFilter::weigh: the TBB-parallel measurement update (a template, so the
// likelihood inlines into the per-particle loop and simple ones vectorise).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

namespace luxloc {

template <typename PerParticle>
bool ParticleFilter::weigh_particles(const PerParticle& loglik) {
  if (!initialized_) return false;
  const std::size_t n = set_.size();
  // New log weight = normalised prior + log-likelihood. Uniform prior: written in place
  // (a refused update leaves the weights uniform); otherwise into the spare buffer, so a
  // refused update leaves the current weights untouched.
  const bool uniform = uniform_;
  FloatVector& target = uniform ? log_w_ : log_w_next_;
  target.resize(n);
  chunk_w_next_.resize(particle_chunks(n));
  lin_w_next_.resize(n);
  const float prior_uniform = -std::log(static_cast<float>(n));
  const float norm = static_cast<float>(log_norm_);
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    float* out = target.data();
    const float* lw = log_w_.data();
    constexpr float kMax = std::numeric_limits<float>::max();
    constexpr float kNegInf = -std::numeric_limits<float>::infinity();
    if (uniform) {
      for (std::size_t i = b; i < e; ++i) {
        const float l = static_cast<float>(loglik(i));
        out[i] = prior_uniform + (l <= kMax ? l : kNegInf);  // NaN / +inf guard
      }
    } else {
      for (std::size_t i = b; i < e; ++i) {
        const float l = static_cast<float>(loglik(i));
        out[i] = (lw[i] - norm) + (l <= kMax ? l : kNegInf);
      }
    }
    chunk_w_next_[c] = exp_chunk(out + b, e - b, lin_w_next_.data() + b);
  });
  if (!commit_weights()) return false;
  if (!uniform) std::swap(log_w_, log_w_next_);
  return true;
}

template <typename Block>
bool ParticleFilter::weigh_blocks(const Block& loglik_block) {
  // As weigh_particles, the log-likelihoods computed a block of particles at a time.
  if (!initialized_) return false;
  const std::size_t n = set_.size();
  const bool uniform = uniform_;
  FloatVector& target = uniform ? log_w_ : log_w_next_;
  target.resize(n);
  chunk_w_next_.resize(particle_chunks(n));
  lin_w_next_.resize(n);
  const float prior_uniform = -std::log(static_cast<float>(n));
  const float norm = static_cast<float>(log_norm_);
  for_each_particle_chunk(n, [&](std::size_t c, std::size_t b, std::size_t e) {
    float* out = target.data();
    const float* lw = log_w_.data();
    constexpr float kMax = std::numeric_limits<float>::max();
    constexpr float kNegInf = -std::numeric_limits<float>::infinity();
    constexpr std::size_t kBlock = 256;
    alignas(32) float l[kBlock];
    for (std::size_t blk = b; blk < e; blk += kBlock) {
      const std::size_t len = std::min(kBlock, e - blk);
      loglik_block(blk, len, l);
      for (std::size_t k = 0; k < len; ++k) {
        const float g = l[k] <= kMax ? l[k] : kNegInf;  // NaN / +inf guard
        out[blk + k] = (uniform ? prior_uniform : lw[blk + k] - norm) + g;
      }
    }
    chunk_w_next_[c] = exp_chunk(out + b, e - b, lin_w_next_.data() + b);
  });
  if (!commit_weights()) return false;
  if (!uniform) std::swap(log_w_, log_w_next_);
  return true;
}

template <typename LogLikelihood>
bool ParticleFilter::weigh(const LogLikelihood& log_likelihood) {
  const double ox = origin_.x(), oy = origin_.y();
  const float* x = set_.x.data();
  const float* y = set_.y.data();
  if constexpr (requires(const LogLikelihood& f, const float* p, float* o) {
                  f.log_likelihood_block(0.0, 0.0, p, p, p, std::size_t{}, o);
                }) {
    // A likelihood with a block path (ReprojectionLikelihood: eight particles at a time).
    flush_heading_walk();
    const float* e = set_.heading ? set_.yaw.data() : nullptr;
    return weigh_blocks([&](std::size_t i, std::size_t len, float* out) {
      log_likelihood.log_likelihood_block(ox, oy, x + i, y + i, e ? e + i : nullptr, len, out);
    });
  } else if constexpr (std::is_invocable_v<const LogLikelihood&, double, double, double>) {
    flush_heading_walk();  // the offsets this likelihood reads must be current
    const float* e = set_.heading ? set_.yaw.data() : nullptr;
    return weigh_particles([&](std::size_t i) {
      return log_likelihood(ox + static_cast<double>(x[i]), oy + static_cast<double>(y[i]),
                            e ? static_cast<double>(e[i]) : 0.0);
    });
  } else {
    return weigh_particles([&](std::size_t i) {
      return log_likelihood(ox + static_cast<double>(x[i]), oy + static_cast<double>(y[i]));
    });
  }
}

}  // namespace luxloc
