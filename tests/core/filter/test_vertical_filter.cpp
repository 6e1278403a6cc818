// The camera's height state (core/filter/vertical_filter.cpp, issue 16 part 3).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "core/filter/vertical_filter.hpp"

using namespace luxloc;

namespace {
TimeNs at(double s) { return static_cast<TimeNs>(std::llround(s * 1e9)); }
double climb(double t) { return 1.1 + 0.6 * std::sin(2.0 * 3.14159265358979 * t / 20.0); }  // the sim drone's
}  // namespace

TEST_CASE("vertical filter follows a climbing device from noisy heights, its sigma honest", "[filter][height]") {
  VerticalFilter f(VerticalFilterOptions{}, 1.1);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.05);
  double sum2 = 0.0;
  int count = 0, inside = 0;
  for (int k = 0; k < 1800; ++k) {  // 60 s at 30 Hz
    const double t = k / 30.0;
    f.update(at(t), climb(t) + n(rng), 0.05);
    if (t < 5.0) continue;
    const double e = f.height_m() - climb(t);
    sum2 += e * e;
    inside += std::abs(e) <= 1.96 * f.height_sigma_m() ? 1 : 0;
    ++count;
  }
  const double rms = std::sqrt(sum2 / count);
  INFO("rms " << rms << " m, within 1.96 sigma " << 100.0 * inside / count << " %");
  CHECK(rms < 0.025);
  CHECK(inside > 0.85 * count);
  CHECK(f.stats().used + f.stats().gated == 1800);
  CHECK(f.stats().gated < 10);  // 3-sigma gate: ~0.3 % of honest heights
}

TEST_CASE("vertical filter gates an outlier, and reopens after a run of them (the state was wrong)", "[filter][height]") {
  VerticalFilter f(VerticalFilterOptions{}, 1.0);
  for (int k = 0; k < 60; ++k) f.update(at(k / 30.0), 1.0, 0.03);
  CHECK(f.update(at(2.0), 2.0, 0.03) == VerticalFilter::Outcome::gated);
  CHECK(f.height_m() == Approx(1.0).margin(0.01));
  // The device was put on a 1 m shelf: five frames in a row disagree, the sixth reopens.
  double t = 2.0;
  for (int k = 0; k < 30; ++k) f.update(at(t += 1.0 / 30.0), 2.0, 0.03);
  CHECK(f.stats().reopened >= 1);
  CHECK(f.height_m() == Approx(2.0).margin(0.05));
  // Garbage in: skipped, never a NaN state.
  CHECK(f.update(at(t + 0.1), std::nan(""), 0.03) == VerticalFilter::Outcome::skipped);
  CHECK(f.update(at(t + 0.1), 1.0, -1.0) == VerticalFilter::Outcome::skipped);
  CHECK(std::isfinite(f.height_m()));
}
