#include "core/filter/resampling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_scan.h>

#include "core/filter/fast_rng.hpp"

namespace luxloc {

ResamplingScheme parse_resampling_scheme(const std::string& name) {
  if (name == "systematic") return ResamplingScheme::Systematic;
  if (name == "stratified") return ResamplingScheme::Stratified;
  if (name == "multinomial") return ResamplingScheme::Multinomial;
  if (name == "residual") return ResamplingScheme::Residual;
  throw std::invalid_argument("unknown resampling scheme '" + name +
                              "' (systematic, stratified, multinomial, residual)");
}

std::string to_string(ResamplingScheme s) {
  switch (s) {
    case ResamplingScheme::Systematic: return "systematic";
    case ResamplingScheme::Stratified: return "stratified";
    case ResamplingScheme::Multinomial: return "multinomial";
    case ResamplingScheme::Residual: return "residual";
  }
  return "?";
}

namespace {

constexpr std::size_t kParallelMin = 16384;

// Inclusive prefix sums of the weights, scaled by m: c[i] = m * sum_{j<=i} w_j.
void scaled_cumsum(std::span<const double> w, std::size_t m, std::vector<double>& c) {
  const std::size_t n = w.size();
  c.resize(n);
  const double scale = static_cast<double>(m);
  if (n < kParallelMin) {
    double acc = 0.0;
    for (std::size_t i = 0; i < n; ++i) c[i] = (acc += w[i] * scale);
    return;
  }
  tbb::parallel_scan(
      tbb::blocked_range<std::size_t>(0, n, 8192), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double sum, bool final_pass) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          sum += w[i] * scale;
          if (final_pass) c[i] = sum;
        }
        return sum;
      },
      [](double a, double b) { return a + b; });
}

// Child k takes the particle i with c[i-1] <= k + u_k < c[i]. With one u for all children
// (systematic) or one per child (stratified), each particle's children form a contiguous
// block that can be written independently: parallel over particles.
void comb(const std::vector<double>& c, const std::vector<double>* u_per_child, double u,
          std::vector<std::uint32_t>& out) {
  const std::size_t n = c.size();
  const std::size_t m = out.size();
  const double dm = static_cast<double>(m);
  auto body = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double lo = i == 0 ? 0.0 : std::min(c[i - 1], dm);
      // The last particle closes the interval at m whatever rounding left in c[n-1].
      const double hi = (i + 1 == n) ? dm + 1.0 : std::min(c[i], dm);
      // children k with k + u_k in [lo, hi)
      std::size_t k = static_cast<std::size_t>(std::max(0.0, std::ceil(lo - 1.0)));
      for (; k < m; ++k) {
        const double pos = static_cast<double>(k) + (u_per_child ? (*u_per_child)[k] : u);
        if (pos >= hi) break;
        if (pos >= lo) out[k] = static_cast<std::uint32_t>(i);
      }
    }
  };
  if (n < kParallelMin) {
    body(0, n);
  } else {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  }
}

}  // namespace

void resample(ResamplingScheme scheme, std::span<const double> weights, std::uint64_t seed,
              std::vector<std::uint32_t>& ancestors, std::size_t children) {
  const std::size_t n = weights.size();
  const std::size_t m = children ? children : n;
  ancestors.resize(m);
  if (n == 0) {
    ancestors.clear();
    return;
  }
  FastRng rng(seed);
  std::vector<double> c;
  switch (scheme) {
    case ResamplingScheme::Systematic: {
      scaled_cumsum(weights, m, c);
      comb(c, nullptr, rng.uniform(), ancestors);
      return;
    }
    case ResamplingScheme::Stratified: {
      scaled_cumsum(weights, m, c);
      std::vector<double> u(m);
      for (auto& x : u) x = rng.uniform();
      comb(c, &u, 0.0, ancestors);
      return;
    }
    case ResamplingScheme::Multinomial: {
      scaled_cumsum(weights, m, c);
      for (std::size_t k = 0; k < m; ++k) {
        const double pos = rng.uniform() * static_cast<double>(m);
        const auto it = std::upper_bound(c.begin(), c.end(), pos);
        ancestors[k] = static_cast<std::uint32_t>(std::min<std::size_t>(n - 1, static_cast<std::size_t>(it - c.begin())));
      }
      return;
    }
    case ResamplingScheme::Residual: {
      // Deterministic floor(n w_i) copies, the remainder drawn multinomially from the residuals.
      std::size_t k = 0;
      std::vector<double> residual(n);
      for (std::size_t i = 0; i < n; ++i) {
        const double nw = weights[i] * static_cast<double>(m);
        const auto copies = static_cast<std::size_t>(std::floor(nw));
        for (std::size_t j = 0; j < copies && k < m; ++j) ancestors[k++] = static_cast<std::uint32_t>(i);
        residual[i] = nw - static_cast<double>(copies);
      }
      if (k < m) {
        double acc = 0.0;
        for (auto& r : residual) r = (acc += r);
        for (; k < m; ++k) {
          const double pos = rng.uniform() * acc;
          const auto it = std::upper_bound(residual.begin(), residual.end(), pos);
          ancestors[k] = static_cast<std::uint32_t>(std::min<std::size_t>(n - 1, static_cast<std::size_t>(it - residual.begin())));
        }
      }
      return;
    }
  }
}

}  // namespace luxloc
