// Heel-strike impacts out of the vertical acceleration (core/imu/impact_filter.hpp): a clean
// stream passes unchanged and undelayed; a 12 g spike on the bounce's peak is replaced by the
// bounce; a lasting change is handed on as measured; nothing is lost or reordered.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/filter/fast_rng.hpp"
#include "core/imu/impact_filter.hpp"

using namespace luxloc;

namespace {

constexpr double kPi = std::numbers::pi;

// A 2 Hz bounce of +-3 m/s^2 (peaks at t = k / 2 s) sampled at `rate_hz`, with sensor noise.
double bounce(double t) { return 3.0 * std::cos(2.0 * kPi * 2.0 * t); }

// The simulator's impact (GaitOptions::heel_impact_mps2): A (1 - tau^2 / w^2) exp(-tau^2 / 2 w^2).
double impact(double t, double a, double w = 0.012) {
  const double tk = std::round(2.0 * t) / 2.0, tau = t - tk;
  return a * (1.0 - tau * tau / (w * w)) * std::exp(-0.5 * tau * tau / (w * w));
}

struct Run {
  std::vector<TimeNs> t;
  std::vector<double> a;
};

Run filter(ImpactFilter& f, double rate_hz, double seconds, double impact_mps2, double noise, std::uint64_t seed = 1) {
  FastRng rng(seed);
  Run out;
  for (int k = 0; k < static_cast<int>(seconds * rate_hz); ++k) {
    const double t = 0.3 + k / rate_hz;
    const double x = bounce(t) + impact(t, impact_mps2) + noise * rng.normal();
    for (const auto& [ts, a] : f.update(seconds_to_ns(t), x)) {
      out.t.push_back(ts);
      out.a.push_back(a);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("ImpactFilter: a walk without impacts passes sample by sample, unchanged", "[imu][impact]") {
  for (const double rate : {50.0, 100.0, 200.0}) {
    ImpactFilter f;
    FastRng rng(3);
    for (int k = 0; k < static_cast<int>(20 * rate); ++k) {
      const double t = k / rate, x = 2.0 * bounce(t) + 0.05 * rng.normal();  // +-6 m/s^2: the bounciest walker
      const auto& out = f.update(seconds_to_ns(t), x);
      REQUIRE(out.size() == 1);
      CHECK(out[0].first == seconds_to_ns(t));
      CHECK(out[0].second == x);
      CHECK(f.current() == x);
    }
    CHECK(f.repaired() == 0);
  }
}

TEST_CASE("ImpactFilter: 12 g heel strikes on the bounce's peak are replaced by the bounce", "[imu][impact]") {
  for (const double rate : {100.0, 200.0, 400.0}) {
    INFO("rate " << rate << " Hz");
    ImpactFilter f;
    const Run r = filter(f, rate, 10.0, 11.0 * 9.81, 0.04);
    // Every sample comes out once, in order.
    REQUIRE(r.t.size() == static_cast<std::size_t>(10.0 * rate));
    for (std::size_t i = 1; i < r.t.size(); ++i) REQUIRE(r.t[i] > r.t[i - 1]);
    double worst = 0.0, t_worst = 0.0;
    for (std::size_t i = 0; i < r.t.size(); ++i)
      if (const double e = std::abs(r.a[i] - bounce(ns_to_seconds(r.t[i]))); e > worst) {
        worst = e;
        t_worst = ns_to_seconds(r.t[i]);
      }
    INFO("worst at " << t_worst << " s");
    // Against 108 m/s^2 spikes: only the spike's leading edge is left as measured (samples
    // that moved by less than max_jump, or max_jerk above 100 Hz).
    CHECK(worst < f.options().max_jump_mps2 + 1.0);
    // What the step detector weighs, the swing of its 0.1 s moving average over each step
    // (the Weinberg length's input), stays within 6 % of the clean bounce's (12 m/s^2 peak to
    // peak, 6 m/s^2 swing); without the filter it is 40 % off.
    const std::size_t n = static_cast<std::size_t>(0.1 * rate);
    std::vector<double> ma, ma_clean;
    double sum = 0.0, clean = 0.0;
    for (std::size_t i = 0; i < r.t.size(); ++i) {
      sum += r.a[i];
      clean += bounce(ns_to_seconds(r.t[i]));
      if (i >= n) {
        sum -= r.a[i - n];
        clean -= bounce(ns_to_seconds(r.t[i - n]));
      }
      ma.push_back(sum / static_cast<double>(n));
      ma_clean.push_back(clean / static_cast<double>(n));
    }
    const std::size_t step = static_cast<std::size_t>(0.5 * rate);
    for (std::size_t k = n; k + step <= ma.size(); k += step) {
      const auto [lo, hi] = std::minmax_element(ma.begin() + k, ma.begin() + k + step);
      const auto [clo, chi] = std::minmax_element(ma_clean.begin() + k, ma_clean.begin() + k + step);
      CHECK((*hi - *lo) == Approx(*chi - *clo).epsilon(0.06));
    }
    CHECK(f.repaired() > 20 * 4);
    // Without the filter the same stream peaks at 11 g.
    ImpactFilterOptions off;
    off.max_jump_mps2 = 0.0;
    ImpactFilter none(off);
    const Run raw = filter(none, rate, 10.0, 11.0 * 9.81, 0.04);
    double peak = 0.0;
    for (double a : raw.a) peak = std::max(peak, a);
    CHECK(peak > 90.0);
  }
}

TEST_CASE("ImpactFilter: a lasting change is handed on as measured, an impact at the start too", "[imu][impact]") {
  ImpactFilter f;
  std::vector<std::pair<TimeNs, double>> out;
  // Still, then the device is put down hard: +6 m/s^2 for 1 s (longer than max_hold).
  for (int k = 0; k < 300; ++k) {
    const double t = k / 100.0, x = (t >= 1.0 && t < 2.0) ? 6.0 : 0.0;
    for (const auto& s : f.update(seconds_to_ns(t), x)) out.push_back(s);
  }
  REQUIRE(out.size() == 300);
  for (int k = 0; k < 300; ++k) {
    const double t = k / 100.0;
    CHECK(out[k].first == seconds_to_ns(t));
    CHECK(out[k].second == ((t >= 1.0 && t < 2.0) ? 6.0 : 0.0));
  }
  CHECK(f.repaired() == 0);
  // NaN and a time that does not advance are dropped, not handed on.
  CHECK(f.update(seconds_to_ns(3.0), std::nan("")).empty());
  CHECK(f.update(seconds_to_ns(3.01), 0.0).size() == 1);
  CHECK(f.update(seconds_to_ns(3.01), 0.0).empty());
  CHECK(f.update(seconds_to_ns(2.5), 0.0).empty());
  CHECK(f.update(seconds_to_ns(3.02), 0.0).size() == 1);
}
