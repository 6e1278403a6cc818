// Stripe-period estimator (core/vlc/stripe_period.cpp): sub-row precision, harmonics,
// real rolling-shutter data.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "core/vlc/stripe_period.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

// Rolling-shutter row profile of a square wave (duty d, period P rows, phase) seen with an
// exposure of e rows: the on-fraction of each row's exposure window, plus noise.
std::vector<double> square_profile(int n, double period, double duty, double phase, double exposure_rows,
                                   double noise, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, noise);
  std::vector<double> y(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    constexpr int kSub = 32;
    double on = 0;
    for (int s = 0; s < kSub; ++s) {
      const double t = v + exposure_rows * (s + 0.5) / kSub;
      const double x = t / period + phase;
      on += (x - std::floor(x)) < duty ? 1.0 : 0.0;
    }
    y[static_cast<std::size_t>(v)] = 200.0 * on / kSub + 10.0 + g(rng);
  }
  return y;
}

}  // namespace

TEST_CASE("stripe period of a sinusoid is found to a small fraction of a row", "[vlc]") {
  for (double period : {7.3, 12.0, 23.7}) {
    std::vector<double> y(90);
    for (int v = 0; v < 90; ++v) y[static_cast<std::size_t>(v)] = 50 + 40 * std::cos(2 * std::numbers::pi * v / period + 0.7);
    const StripePeriodEstimate e = estimate_stripe_period(y, 5.0, 40.0);
    REQUIRE(e.valid);
    CHECK(e.period_rows == Approx(period).epsilon(1e-6));
    CHECK(e.explained > 0.999);
    CHECK(e.subharmonic == 1);
  }
}

TEST_CASE("stripe period of noisy square waves: sub-row precision, fundamental not harmonic", "[vlc]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const double period = 6.0 + 30.0 * U(rng);
    const int n = static_cast<int>(period * (2.0 + 4.0 * U(rng)));  // 2 to 6 periods
    const double duty = 0.3 + 0.4 * U(rng);
    const auto y = square_profile(n, period, duty, U(rng), 1.5, 4.0, rng);
    // The search range spans more than 3:1, so 3rd harmonics are inside it.
    const StripePeriodEstimate e = estimate_stripe_period(y, period / 2.2, period * 1.6);
    REQUIRE(e.valid);
    worst = std::max(worst, std::abs(e.period_rows - period) / period);
  }
  INFO("worst relative period error " << worst);
  CHECK(worst < 0.05);  // never a harmonic (that would be >= 50 %)
}

TEST_CASE("a harmonic peak with a weak fundamental is traced back to the fundamental", "[vlc]") {
  // The 3rd harmonic made as strong as the fundamental.
  std::vector<double> y(120);
  const double P = 30.0;
  for (int v = 0; v < 120; ++v)
    y[static_cast<std::size_t>(v)] = 100 + 20 * std::cos(2 * std::numbers::pi * v / P) + 30 * std::cos(6 * std::numbers::pi * v / P);
  const StripePeriodEstimate e = estimate_stripe_period(y, 8.0, 40.0);
  REQUIRE(e.valid);
  CHECK(e.period_rows == Approx(P).epsilon(0.01));
  CHECK(e.subharmonic == 3);
}

TEST_CASE("stripe period: weights mask rows, degenerate inputs are invalid", "[vlc]") {
  std::vector<double> y(60), w(60, 1.0);
  for (int v = 0; v < 60; ++v) y[static_cast<std::size_t>(v)] = std::sin(2 * std::numbers::pi * v / 11.0);
  for (int v = 20; v < 30; ++v) {
    y[static_cast<std::size_t>(v)] = 1e6;  // garbage, masked
    w[static_cast<std::size_t>(v)] = 0.0;
  }
  const StripePeriodEstimate e = estimate_stripe_period(y, w, 5.0, 30.0);
  REQUIRE(e.valid);
  CHECK(e.period_rows == Approx(11.0).epsilon(1e-4));

  CHECK_FALSE(estimate_stripe_period(std::vector<double>(40, 3.0), 5.0, 30.0).valid);  // flat
  CHECK_FALSE(estimate_stripe_period(std::vector<double>{1, 2, 3}, 5.0, 30.0).valid);   // too short
  CHECK_FALSE(estimate_stripe_period(y, 30.0, 5.0).valid);                                // empty range
  std::vector<double> bad = y;
  bad[3] = std::nan("");
  const StripePeriodEstimate nanrow = estimate_stripe_period(bad, 5.0, 30.0);  // a NaN row is skipped
  REQUIRE(nanrow.valid);
  CHECK(std::isfinite(nanrow.period_rows));
}

TEST_CASE("real full-frame stripes (1000 Hz, 14.57 us/row) give 68.6 rows within 0.3 %", "[vlc]") {
  const auto path = test::shared_dir() / "realdata/rolling_shutter_readout/frame_example.png";
  const cv::Mat img = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  REQUIRE_FALSE(img.empty());
  std::vector<double> profile(static_cast<std::size_t>(img.rows));
  for (int r = 0; r < img.rows; ++r) profile[static_cast<std::size_t>(r)] = cv::mean(img.row(r))[0];
  const StripePeriodEstimate e = estimate_stripe_period(profile, 20.0, 200.0);
  REQUIRE(e.valid);
  INFO("period " << e.period_rows << " rows, sigma " << e.period_sigma_rows);
  CHECK(std::abs(e.period_rows - 68.6) / 68.6 < 0.003);
  // Row time from the known LED frequency (what a `calib camera` step would do).
  const double row_time_us = 1e6 / (1000.0 * e.period_rows);
  CHECK(row_time_us == Approx(14.57).epsilon(0.003));
}
