// Stripe period from the stripe edges (short blobs, < 2 periods): box-filtered square waves.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "core/vlc/stripe_period.hpp"

using namespace luxloc;

namespace {

// Row means of a square wave (period P rows, duty d, phase in periods) box-filtered over
// `exposure_rows`, plus a dim rim of `rim` rows at each end and Gaussian noise.
std::vector<double> stripes(int rows, double P, double d, double phase, double exposure_rows, int rim, double noise,
                            std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, noise);
  std::vector<double> y(static_cast<std::size_t>(rows));
  const auto on_time = [&](double x) { return std::floor(x) * d + std::min(x - std::floor(x), d); };  // periods
  for (int r = 0; r < rows; ++r) {
    const double x0 = r / P + phase, x1 = (r + exposure_rows) / P + phase;
    double v = 200.0 * (on_time(x1) - on_time(x0)) / (x1 - x0);
    if (r < rim || r >= rows - rim) v *= 0.3;
    y[static_cast<std::size_t>(r)] = v + n(rng);
  }
  return y;
}

}  // namespace

TEST_CASE("edge period: 1.2-2 periods of a box-filtered square wave, any phase, within 2 %", "[vlc]") {
  std::mt19937_64 rng(11);
  int valid = 0, total = 0;
  for (double P : {20.0, 26.0, 33.3})
    for (double span : {1.2, 1.5, 1.9})
      for (double phase = 0.0; phase < 1.0; phase += 0.1) {
        const int rows = static_cast<int>(span * P);
        const auto y = stripes(rows, P, 0.5, phase, 3.3, 1, 2.0, rng);
        const EdgePeriodEstimate e = estimate_period_from_edges(y, {}, 0.5, 5.0, 60.0);
        ++total;
        if (!e.valid) continue;
        ++valid;
        INFO("P " << P << " span " << span << " phase " << phase << " -> " << e.period_rows << " (" << e.edges << " edges)");
        CHECK(std::abs(e.period_rows - P) < 0.02 * P);
        CHECK(e.period_sigma_rows > 0);
        CHECK(e.period_sigma_rows < 0.05 * P);
      }
  INFO(valid << " of " << total);
  CHECK(valid >= 0.7 * total);  // the rest: fewer than two edges away from the ends
}

TEST_CASE("edge period: duty other than 0.5, no whole stripe, and inconsistent edges are refused", "[vlc]") {
  std::mt19937_64 rng(12);
  // Duty 0.3: a bright stripe is 0.3 P wide, a dark one 0.7 P.
  int valid = 0;
  for (double phase = 0.0; phase < 1.0; phase += 0.125) {
    const auto y = stripes(45, 30.0, 0.3, phase, 3.0, 1, 1.0, rng);
    const EdgePeriodEstimate e = estimate_period_from_edges(y, {}, 0.3, 5.0, 60.0);
    if (!e.valid) continue;
    ++valid;
    CHECK(std::abs(e.period_rows - 30.0) < 0.6);
  }
  CHECK(valid >= 4);
  // Less than one stripe: one edge at most.
  const auto short_blob = stripes(14, 33.0, 0.5, 0.1, 3.3, 1, 1.0, rng);
  CHECK_FALSE(estimate_period_from_edges(short_blob, {}, 0.5, 5.0, 60.0).valid);
  // One bright stripe of 10 rows inside 40 dark rows: as a 50 % duty wave its period would be
  // 20 rows, so the dark run after it (25 rows) should have ended in an edge: refused.
  std::vector<double> y(50, 5.0);
  for (int r = 10; r < 20; ++r) y[static_cast<std::size_t>(r)] = 200.0;
  CHECK_FALSE(estimate_period_from_edges(y, {}, 0.5, 5.0, 60.0).valid);
  // Zero weights split the profile: no edge across a gap.
  std::vector<double> w(50, 1.0);
  CHECK_FALSE(estimate_period_from_edges(std::vector<double>(50, 7.0), w, 0.5, 5.0, 60.0).valid);  // flat
}
