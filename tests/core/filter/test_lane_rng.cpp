#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/filter/lane_rng.hpp"
#include "core/filter/simd8.hpp"

using namespace luxloc;

TEST_CASE("LaneRng normals have the standard normal's moments and tails", "[filter]") {
  LaneRng rng(1, 2, 3);
  std::vector<float> v(1 << 20);
  rng.fill_normal(v.data(), v.size());
  double m = 0, s2 = 0, s4 = 0;
  std::size_t over1 = 0, over2 = 0, over3 = 0;
  for (float x : v) {
    m += x;
    s2 += x * x;
    s4 += static_cast<double>(x) * x * x * x;
    over1 += std::abs(x) > 1;
    over2 += std::abs(x) > 2;
    over3 += std::abs(x) > 3;
  }
  const double n = static_cast<double>(v.size());
  REQUIRE(m / n == Approx(0.0).margin(0.005));
  REQUIRE(s2 / n == Approx(1.0).margin(0.005));
  REQUIRE(s4 / n == Approx(3.0).margin(0.03));  // kurtosis
  REQUIRE(over1 / n == Approx(0.31731).margin(0.002));
  REQUIRE(over2 / n == Approx(0.04550).margin(0.001));
  REQUIRE(over3 / n == Approx(0.00270).margin(0.0002));
  // Same stream key, same numbers.
  LaneRng again(1, 2, 3);
  std::vector<float> w(v.size());
  again.fill_normal(w.data(), w.size());
  REQUIRE(v == w);
}

TEST_CASE("LaneRng uniforms and triangular variates", "[filter]") {
  LaneRng rng(9, 1);
  std::vector<float> u(1 << 18), t(1 << 18);
  rng.fill_uniform(u.data(), u.size());
  rng.fill_triangular(t.data(), t.size());
  double mu = 0, mt = 0, vt = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    REQUIRE(u[i] > 0.0f);
    REQUIRE(u[i] < 1.0f);
    REQUIRE(std::abs(t[i]) < 2.45f);
    mu += u[i];
    mt += t[i];
    vt += t[i] * t[i];
  }
  const double n = static_cast<double>(u.size());
  REQUIRE(mu / n == Approx(0.5).margin(0.003));
  REQUIRE(mt / n == Approx(0.0).margin(0.01));
  REQUIRE(vt / n == Approx(1.0).margin(0.01));
}

TEST_CASE("simd8 exp and log agree with std", "[filter]") {
  using namespace simd8;
  for (float base : {-100.0f, -87.5f, -50.0f, -10.0f, -1.0f, -1e-3f, 0.0f}) {
    F8 x;
    for (int l = 0; l < 8; ++l) x[l] = base + 0.1f * static_cast<float>(l) * (base < -0.5f ? 1.0f : -1.0f);
    const F8 e = exp_nonpositive(x);
    for (int l = 0; l < 8; ++l) {
      if (x[l] < -87.0f) {
        REQUIRE(e[l] == 0.0f);
      } else {
        REQUIRE(e[l] == Approx(std::exp(x[l])).epsilon(1e-6));
      }
    }
  }
  F8 inf = splat(-std::numeric_limits<float>::infinity());
  REQUIRE(exp_nonpositive(inf)[0] == 0.0f);
  for (float u : {1e-7f, 1e-3f, 0.3f, 0.70710677f, 0.9999f, 1.0f, 5.0f}) {
    const F8 l = log_positive(splat(u));
    REQUIRE(l[3] == Approx(std::log(u)).epsilon(1e-6).margin(1e-7));
    const F8 r = sqrt_nonnegative(splat(u));
    REQUIRE(r[5] == Approx(std::sqrt(u)).epsilon(1e-6));
  }
  REQUIRE(sqrt_nonnegative(F8{})[0] == 0.0f);
}
