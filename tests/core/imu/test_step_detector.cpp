#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/filter/fast_rng.hpp"
#include "core/imu/step_detector.hpp"
#include "core/imu/step_length.hpp"
#include "core/imu/step_matching.hpp"

using namespace luxloc;

namespace {

// Vertical acceleration of a walker from t0 to t1: starting and ending in a trough, peaks of
// `amp` at heel strikes t0 + (k + 1/2) / f.
std::vector<DetectedStep> detect(double f, double amp, double t0, double t1, double noise, double duration,
                                 std::vector<double>* truth, const StepDetectorOptions& o = {}) {
  StepDetector d(o);
  FastRng rng(7);
  std::vector<DetectedStep> out;
  for (int k = 0; k * 0.01 < duration; ++k) {
    const double t = k * 0.01;
    const bool walking = t >= t0 && t < t1;
    const double a = walking ? -amp * std::cos(2 * std::numbers::pi * f * (t - t0)) : 0.0;
    if (auto s = d.update(seconds_to_ns(t), a + noise * rng.normal())) out.push_back(*s);
  }
  if (auto s = d.flush()) out.push_back(*s);
  if (truth)
    for (double t = t0 + 0.5 / f; t < t1; t += 1.0 / f) truth->push_back(t);
  return out;
}

std::vector<double> times(const std::vector<DetectedStep>& s) {
  std::vector<double> t;
  for (const auto& x : s) t.push_back(ns_to_seconds(x.t));
  return t;
}

}  // namespace

TEST_CASE("StepDetector finds every heel strike of a clean gait, on time", "[imu]") {
  std::vector<double> truth;
  const auto steps = detect(1.8, 2.0, 2.0, 2.0 + 54 / 1.8, 0.05, 35.0, &truth);
  REQUIRE(truth.size() == 54);
  const StepMatch m = match_steps(times(steps), truth, 0.05);
  CHECK(m.matched == truth.size());
  CHECK(m.false_steps() == 0);
  CHECK(m.max_offset_s <= 0.02);  // the centred average does not delay the peak
  // Swing ~ peak-to-peak (4 m/s^2), slightly reduced by the 0.1 s average; cadence recovered.
  CHECK(steps[5].swing() == Approx(4.0).epsilon(0.08));
  CHECK(steps[5].interval_s == Approx(1 / 1.8).margin(0.015));
  CHECK(steps[0].interval_s == 0.0);  // first step after standing: no interval
}

TEST_CASE("StepDetector stays silent at rest and on small swings, merges double peaks", "[imu]") {
  CHECK(detect(1.8, 0.0, 0, 0, 0.05, 20.0, nullptr).empty());
  CHECK(detect(1.8, 0.3, 0, 20, 0.02, 20.0, nullptr).empty());  // swing 0.6 < 0.8 m/s^2
  // A double peak per heel strike (two bumps 0.12 s apart): one step each.
  StepDetector d;
  int n = 0;
  for (int k = 0; k < 1000; ++k) {
    const double t = k * 0.01, ph = std::fmod(t, 0.6);
    const double a = 2.0 * std::exp(-std::pow((ph - 0.2) / 0.04, 2)) + 1.6 * std::exp(-std::pow((ph - 0.32) / 0.04, 2)) - 0.6;
    n += d.update(seconds_to_ns(t), a).has_value();
  }
  CHECK(n >= 15);
  CHECK(n <= 17);  // 10 s / 0.6 s = 16.7 strides
}

TEST_CASE("Step-length models: Weinberg, cadence, constant, and Weinberg calibration", "[imu]") {
  DetectedStep s;
  s.peak_mps2 = 2.0;
  s.valley_mps2 = -2.0;
  s.interval_s = 1 / 1.79;
  StepLengthOptions o;
  CHECK(StepLengthModel(o).length_m(s) == Approx(0.5 * std::pow(4.0, 0.25)));
  o.kind = StepLengthKind::cadence;
  CHECK(StepLengthModel(o).length_m(s) == Approx(0.7));
  s.interval_s = 0.5;  // 2 Hz: longer strides
  CHECK(StepLengthModel(o).length_m(s) == Approx(0.7 + 0.227 * 0.21));
  o.kind = StepLengthKind::constant;
  o.a_m = 0.65;
  CHECK(StepLengthModel(o).length_m(s) == Approx(0.65));
  CHECK(StepLengthModel(o).sigma_m(0.65) == Approx(0.065));
  CHECK(parse_step_length_kind("cadence") == StepLengthKind::cadence);
  CHECK_THROWS_AS(parse_step_length_kind("stride"), std::invalid_argument);
  // Calibration: 10 steps of swing 4 over 14.14 m -> K = 14.14 / (10 * sqrt(2)) = 1.
  std::vector<DetectedStep> steps(10, s);
  CHECK(StepLengthModel::calibrate_weinberg(steps, 10 * std::sqrt(2.0)) == Approx(1.0));
  CHECK(std::isnan(StepLengthModel::calibrate_weinberg({}, 10.0)));
}
