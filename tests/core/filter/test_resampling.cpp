#include <catch2/catch.hpp>
#include <cmath>
#include <numeric>

#include "core/filter/fast_rng.hpp"
#include "core/filter/resampling.hpp"

using namespace luxloc;

TEST_CASE("Every resampling scheme copies particles in proportion to their weights", "[filter]") {
  const std::size_t n = GENERATE(1000u, 50000u);  // serial and TBB-parallel paths
  std::vector<double> w(n);
  FastRng rng(7);
  for (auto& x : w) x = rng.uniform() < 0.1 ? 1.0 + rng.uniform() : 0.0;  // 90 % dead particles
  const double sum = std::accumulate(w.begin(), w.end(), 0.0);
  for (auto& x : w) x /= sum;
  for (auto scheme : {ResamplingScheme::Systematic, ResamplingScheme::Stratified, ResamplingScheme::Multinomial,
                      ResamplingScheme::Residual}) {
    INFO(to_string(scheme) << " n=" << n);
    std::vector<std::uint32_t> anc;
    resample(scheme, w, 42, anc);
    REQUIRE(anc.size() == n);
    std::vector<double> copies(n, 0.0);
    for (auto a : anc) {
      REQUIRE(a < n);
      copies[a] += 1.0;
    }
    double dead_copies = 0.0, max_dev = 0.0, max_z = 0.0;
    bool below_floor = false;
    for (std::size_t i = 0; i < n; ++i) {
      const double nw = w[i] * static_cast<double>(n);
      if (w[i] == 0.0) dead_copies += copies[i];
      max_dev = std::max(max_dev, std::abs(copies[i] - nw));
      max_z = std::max(max_z, std::abs(copies[i] - nw) / std::sqrt(std::max(nw, 1.0)));
      below_floor |= copies[i] < std::floor(nw);
    }
    REQUIRE(dead_copies == 0.0);  // a zero-weight particle is never copied
    if (scheme == ResamplingScheme::Systematic)
      REQUIRE(max_dev < 1.0 + 1e-9);  // low variance: within one copy of n*w
    else
      REQUIRE(max_z < 6.0);  // random remainder: within 6 binomial sigmas
    if (scheme == ResamplingScheme::Residual) REQUIRE_FALSE(below_floor);  // floor(n w) copies are certain
  }
}

TEST_CASE("Systematic resampling is deterministic for a seed", "[filter]") {
  std::vector<double> w(100, 0.01);
  std::vector<std::uint32_t> a, b;
  resample(ResamplingScheme::Systematic, w, 5, a);
  resample(ResamplingScheme::Systematic, w, 5, b);
  REQUIRE(a == b);
  for (std::size_t i = 0; i < a.size(); ++i) REQUIRE(a[i] == i);  // equal weights: identity
  REQUIRE_THROWS_AS(parse_resampling_scheme("bogus"), std::invalid_argument);
}

TEST_CASE("Resampling draws any number of children (KLD-sampling)", "[filter]") {
  std::vector<double> w = {0.5, 0.25, 0.25, 0.0};
  for (auto scheme : {ResamplingScheme::Systematic, ResamplingScheme::Stratified, ResamplingScheme::Multinomial,
                      ResamplingScheme::Residual}) {
    INFO(to_string(scheme));
    std::vector<std::uint32_t> anc;
    resample(scheme, w, 3, anc, 4000);
    REQUIRE(anc.size() == 4000);
    std::vector<double> c(4, 0.0);
    for (auto a : anc) c.at(a) += 1;
    REQUIRE(c[0] == Approx(2000).margin(120));
    REQUIRE(c[1] == Approx(1000).margin(100));
    REQUIRE(c[3] == 0.0);
    resample(scheme, w, 3, anc, 2);
    REQUIRE(anc.size() == 2);
  }
}
