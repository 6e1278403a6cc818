// MotionSource (core/fusion/motion_source.cpp): the pdr model's regimes around a stop.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "core/fusion/motion_source.hpp"
#include "core/imu/sim_walk.hpp"

using namespace luxloc;

TEST_CASE("pdr motion: a walk's last steps are paid out after the walker stops, then nothing moves", "[motion]") {
  // The sim walk stops at 61 s for 2 s (seed 1: at 31 s little is owed). Its last steps are confirmed 0.3 s after their heel
  // strikes, when the bounce has already died: the distance they add must still reach the
  // filter (it was dropped: ~0.2 m short along the walk at every stop).
  const test::SimWalk& w = test::sim_walk(1);
  MotionSource ms;
  TimeNs t_prev = 0;
  bool first = true, stopped = false;
  double output_before_stop = 0.0, paid_still = 0.0, paid_late = 0.0, stop_t = 0.0;
  for (const ImuSample& s : w.imu) {
    const double t = ns_to_seconds(s.t);
    if (t > 62.9) break;
    ms.update(s, w.simulator.truth(t).R_BtoW);
    if (!first) {
      const MotionRegime before = ms.regime();
      const double output_before = ms.gait().output_m();
      const MotionInput u = ms.input(t_prev, s.t);
      if (t > 50.0 && !stopped && before == MotionRegime::gait && ms.regime() == MotionRegime::still) {
        stopped = true;
        stop_t = t;
        output_before_stop = output_before;
      }
      if (stopped && u.has_gait) {
        paid_still += u.gait.speed_mps * u.dt;
        if (t >= 62.3) paid_late += u.gait.speed_mps * u.dt;
      }
      if (stopped) CHECK_FALSE(u.has_acc);  // no strapdown while standing
    }
    first = false;
    t_prev = s.t;
  }
  const double owed = ms.gait().expected_m() - output_before_stop;
  INFO("stepping ended at " << stop_t << " s owing " << owed << " m; paid since " << paid_still << " m");
  REQUIRE(stopped);
  CHECK(stop_t > 60.5);
  CHECK(stop_t < 61.8);
  CHECK(ms.regime() == MotionRegime::still);
  CHECK(owed > 0.05);  // the case is real: the last step was confirmed after the bounce died
  CHECK(paid_still == Approx(owed).margin(0.005));
  CHECK(std::abs(ms.gait().output_m() - ms.gait().expected_m()) < 0.005);
  CHECK(paid_late < 0.005);  // standing still moves nothing once it is paid
}

TEST_CASE("pdr motion: what the last steps owe at a stop is paid with along-track noise of half of it", "[motion]") {
  // MotionSourceOptions::stop_owed_sigma (0.7): over the payout the along-track variance the
  // filters add (length_sigma^2 / T per second) sums to f^2 owed^2 / 2, 1 sigma ~0.5 x owed;
  // while walking the per-step noise stays the step's own (5 % of its length).
  const test::SimWalk& w = test::sim_walk(1);
  MotionSource ms;
  TimeNs t_prev = 0;
  bool first = true, stopped = false;
  double var_still = 0.0, output_before_stop = 0.0, max_walking_sigma_share = 0.0;
  for (const ImuSample& s : w.imu) {
    const double t = ns_to_seconds(s.t);
    if (t > 62.9) break;
    ms.update(s, w.simulator.truth(t).R_BtoW);
    if (!first) {
      const MotionRegime before = ms.regime();
      const double output_before = ms.gait().output_m();
      const MotionInput u = ms.input(t_prev, s.t);
      if (t > 50.0 && !stopped && before == MotionRegime::gait && ms.regime() == MotionRegime::still) {
        stopped = true;
        output_before_stop = output_before;
      }
      const double T = u.gait.step_period_s;
      if (stopped && u.has_gait) var_still += u.gait.length_sigma_m * u.gait.length_sigma_m / T * u.dt;
      if (ms.regime() == MotionRegime::gait && u.gait.speed_mps > 0.0 && ms.gait().has_step())
        max_walking_sigma_share =
            std::max(max_walking_sigma_share, u.gait.length_sigma_m / ms.gait().last_step().length_m);
    }
    first = false;
    t_prev = s.t;
  }
  REQUIRE(stopped);
  const double owed = ms.gait().expected_m() - output_before_stop;
  INFO("owed " << owed << " m at the stop, payout sigma " << std::sqrt(var_still) << " m");
  REQUIRE(owed > 0.05);
  // f / sqrt(2) = 0.49 of what is owed, plus (the larger of the two each instant) the step's
  // own 5 % that accrues while the servo pays.
  CHECK(std::sqrt(var_still) >= 0.45 * owed);
  CHECK(std::sqrt(var_still) <= 0.65 * owed);
  CHECK(max_walking_sigma_share == Approx(0.05).margin(1e-6));

  MotionSourceOptions none;
  none.stop_owed_sigma = 0.0;
  MotionSource quiet(none);
  first = true;
  stopped = false;
  double var_quiet = 0.0;
  for (const ImuSample& s : w.imu) {
    const double t = ns_to_seconds(s.t);
    if (t > 62.9) break;
    quiet.update(s, w.simulator.truth(t).R_BtoW);
    if (!first) {
      const MotionRegime before = quiet.regime();
      const MotionInput u = quiet.input(t_prev, s.t);
      if (t > 50.0 && !stopped && before == MotionRegime::gait && quiet.regime() == MotionRegime::still) stopped = true;
      if (stopped && u.has_gait) var_quiet += u.gait.length_sigma_m * u.gait.length_sigma_m / u.gait.step_period_s * u.dt;
    }
    first = false;
    t_prev = s.t;
  }
  CHECK(var_quiet < 0.5 * var_still);  // the step's own 5 % only
}
