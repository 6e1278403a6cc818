// The fixes' persistent innovation that widens the reported sigma
// (core/fusion/innovation_bias.cpp, issue 12 part 3).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/fusion/innovation_bias.hpp"

using namespace luxloc;

namespace {
TimeNs at(double s) { return static_cast<TimeNs>(std::llround(s * 1e9)); }
const Eigen::Matrix2d kS = Eigen::Matrix2d::Identity() * 0.5 * 0.5;  // a 0.5 m fix and a tight filter
}  // namespace

TEST_CASE("innovation bias: white innovations add next to nothing", "[fusion][sigma]") {
  InnovationBias b;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 0.5);
  double extra_sum = 0.0;
  int count = 0;
  for (int i = 0; i < 600; ++i) {  // 10 min of 1 Hz fixes, consistent with S
    b.add(at(i), Eigen::Vector2d(n(rng), n(rng)), kS);
    if (i >= 20) {
      extra_sum += b.extra_variance().sum();
      ++count;
    }
  }
  // The estimate of the squared bias is unbiased around 0, clipped at 0: on average a
  // fraction of the fixes' own variance (0.25 m^2 per axis), here measured ~0.02.
  CHECK(extra_sum / count < 0.05);
  CHECK(b.mean_innovation().norm() < 0.5);
}

TEST_CASE("innovation bias: a filter lagging its fixes by 0.6 m reports it within seconds", "[fusion][sigma]") {
  InnovationBias b;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 0.5);
  for (int i = 0; i < 30; ++i) b.add(at(i), Eigen::Vector2d(n(rng), n(rng)), kS);
  // From 30 s the filter sits 0.6 m off in y (its fixes read +0.6 m on average).
  double first_covered = -1.0;
  for (int i = 30; i < 60; ++i) {
    b.add(at(i), Eigen::Vector2d(n(rng), 0.6 + n(rng)), kS);
    if (first_covered < 0.0 && std::sqrt(b.extra_variance().y()) > 0.3) first_covered = i - 30;
  }
  INFO("first second with an extra sigma_y > 0.3 m: " << first_covered);
  CHECK(first_covered >= 0.0);
  CHECK(first_covered <= 12.0);
  CHECK(std::sqrt(b.extra_variance().y()) == Approx(0.6).margin(0.3));
  CHECK(b.extra_variance().x() < 0.1);
  // Once the filter has caught up, the term fades with the time constant (5 s).
  for (int i = 60; i < 90; ++i) b.add(at(i), Eigen::Vector2d(n(rng), n(rng)), kS);
  CHECK(b.extra_variance().y() < 0.1);
}

TEST_CASE("innovation bias: off, NaN and reset", "[fusion][sigma]") {
  InnovationBiasOptions off;
  off.enabled = false;
  InnovationBias b(off);
  for (int i = 0; i < 20; ++i) b.add(at(i), Eigen::Vector2d(2.0, 0.0), kS);
  CHECK(b.extra_variance().isZero());

  InnovationBias c;
  c.add(at(0), Eigen::Vector2d(std::nan(""), 0.0), kS);
  c.add(at(1), Eigen::Vector2d(0.0, 0.0), Eigen::Matrix2d::Constant(std::nan("")));
  CHECK(c.mean_innovation().isZero());
  for (int i = 2; i < 20; ++i) c.add(at(i), Eigen::Vector2d(2.0, 0.0), kS);
  CHECK(c.extra_variance().x() > 2.0);
  c.reset();
  CHECK(c.extra_variance().isZero());
  CHECK(c.mean_innovation().isZero());
}
