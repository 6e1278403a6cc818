#pragma once
// ParticleFilter::weigh: the TBB-parallel measurement update (template, so the likelihood
// inlines into the per-particle loop).
#include <cmath>
#include <limits>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace luxloc {

template <typename LogLikelihood>
bool ParticleFilter::weigh(const LogLikelihood& log_likelihood) {
  const std::size_t n = set_.size();
  // First pass: likelihoods into scratch, keeping the best one to detect underflow.
  scratch_.log_w.resize(n);
  const double best = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 4096), -std::numeric_limits<double>::infinity(),
      [&](const tbb::blocked_range<std::size_t>& r, double m) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          double l = log_likelihood(set_.x[i], set_.y[i]);
          if (std::isnan(l)) l = -std::numeric_limits<double>::infinity();  // NaN guard
          scratch_.log_w[i] = l;
          m = std::max(m, set_.log_w[i] + l);
        }
        return m;
      },
      [](double a, double b) { return std::max(a, b); });
  if (!std::isfinite(best)) return false;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16384), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) set_.log_w[i] += scratch_.log_w[i];
  });
  return true;
}

}  // namespace luxloc
