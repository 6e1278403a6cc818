#include <catch2/catch.hpp>
#include <cmath>
#include <utility>
#include <vector>

#include "core/imu/gait_speed.hpp"

using namespace luxloc;

namespace {

// A walker bouncing at 1.8 Hz (vertical acceleration 1.5 m/s^2) from t_walk0 to t_walk1,
// 0.7 m steps at every heel strike, each reported confirm_s after it (as the detector
// does). Returns the distance GaitSpeed hands out at 100 Hz, sampled at `probe_s`.
struct Walk {
  double t_walk0 = 1.0, t_walk1 = 11.0, period_s = 1.0 / 1.8, length_m = 0.7, confirm_s = 0.3;
  double end_s = 14.0;
};

double walked_truth(const Walk& w, double t) {
  const double v = w.length_m / w.period_s;
  return v * std::clamp(t - w.t_walk0, 0.0, w.t_walk1 - w.t_walk0);
}

}  // namespace

TEST_CASE("Gait speed follows the walked distance without a step of lag and stops with the walker", "[imu][motion]") {
  const Walk w;
  GaitSpeed gs;
  double next_strike = w.t_walk0 + w.period_s;  // the first heel strike ends the first step
  bool first = true;
  double max_lag = 0.0, at_stop = 0.0;
  TimeNs t_prev = 0;
  for (int k = 0; k <= static_cast<int>(w.end_s * 100); ++k) {
    const double t = k * 0.01;
    const bool walking = t > w.t_walk0 && t < w.t_walk1;
    gs.update(seconds_to_ns(t), walking ? 1.5 * std::cos(2 * M_PI * 1.8 * (t - w.t_walk0)) : 0.01);
    // Steps are confirmed confirm_s after their heel strike.
    while (next_strike <= w.t_walk1 && t >= next_strike + w.confirm_s) {
      Step s;
      s.t = seconds_to_ns(next_strike);
      s.length_m = w.length_m;
      s.interval_s = first ? 0.0 : w.period_s;
      first = false;
      gs.add_step(s);
      next_strike += w.period_s;
    }
    if (k > 0) gs.take_speed(t_prev, seconds_to_ns(t));
    t_prev = seconds_to_ns(t);
    if (t > w.t_walk0 + 2.0 && t < w.t_walk1) max_lag = std::max(max_lag, std::abs(gs.output_m() - walked_truth(w, t)));
    if (std::abs(t - (w.t_walk1 + 2.0)) < 1e-9) at_stop = gs.output_m();
  }
  const double total = walked_truth(w, w.end_s);
  INFO("output " << gs.output_m() << " m, truth " << total << " m, max lag " << max_lag << " m");
  // In steady walking the output stays within a small part of a step of the truth...
  CHECK(max_lag < 0.15);
  // ...it stops when the walker does (no drift while standing) and ends near the truth.
  CHECK(gs.output_m() == Approx(at_stop).margin(1e-9));
  // (This walker stops dead; the extrapolation runs on until the bounce window empties.)
  CHECK(std::abs(gs.output_m() - total) < 0.5);
  // No turning: every step counts in full.
  CHECK(gs.walked_m() == Approx(w.length_m * std::floor((w.t_walk1 - w.t_walk0) / w.period_s + 1e-9)).epsilon(1e-6));
}

TEST_CASE("Gait speed is zero before the first step and never negative or NaN", "[imu][motion]") {
  GaitSpeed gs;
  gs.update(seconds_to_ns(0.0), 0.0);
  CHECK(gs.take_speed(0, seconds_to_ns(0.01)) == 0.0);
  gs.update(seconds_to_ns(0.02), NAN);  // ignored
  Step bad;
  bad.length_m = NAN;
  gs.add_step(bad);  // ignored
  CHECK_FALSE(gs.has_step());
  CHECK(gs.take_speed(seconds_to_ns(0.01), seconds_to_ns(0.02)) == 0.0);
  CHECK(gs.take_speed(seconds_to_ns(0.02), seconds_to_ns(0.02)) == 0.0);  // dt = 0
}

TEST_CASE("Gait speed shortens turning steps by the turn slowdown", "[imu][motion]") {
  GaitSpeedOptions o;
  o.turn_slowdown_s_per_rad = 0.2;
  GaitSpeed gs(o);
  // Bouncing and turning at 1 rad/s for 5 s, a 0.7 m step every 0.5 s once the yaw-rate
  // average has settled (from 2 s).
  for (int k = 0; k <= 500; ++k) {
    const double t = k * 0.01;
    gs.update(seconds_to_ns(t), 1.5 * std::cos(2 * M_PI * 2.0 * t), 0.0, 1.0);
    if (k >= 200 && k % 50 == 30) {  // strikes at 2.0, 2.5, ... confirmed 0.3 s later
      Step s;
      s.t = seconds_to_ns(t - 0.3);
      s.length_m = 0.7;
      s.interval_s = 0.5;
      gs.add_step(s);
    }
  }
  REQUIRE(gs.has_step());
  CHECK(gs.turn_factor() == Approx(0.8).margin(0.01));
  // Six steps of 0.7 m, each counted at 80 %.
  CHECK(gs.walked_m() == Approx(6 * 0.7 * 0.8).margin(0.02));
}

// The turned angle is paid out with the distance it was turned over (GaitSpeed::turn_paid_rps;
// the particle filter's walker loses A metres per radian of it, GaitNoise::turn_slowdown0).
TEST_CASE("Gait speed pays out the turned angle with the distance, and none once the distance stops",
          "[imu][motion]") {
  GaitSpeedOptions no_factor;  // no turn factor of its own: the particle filter's setting
  no_factor.turn_slowdown_s_per_rad = 0.0;
  GaitSpeed gs(no_factor);
  // 6 s bouncing and turning at 1 rad/s with 0.7 m steps every 0.5 s (1.4 m/s: 0.714 rad per
  // metre), then standing still (no bounce, no turn) for 3 s.
  // Measured from 2 s, once the yaw-rate average (turn_window_s) has settled.
  double distance = 0.0, angle = 0.0, angle_while_still = 0.0;
  TimeNs t_prev = 0;
  for (int k = 0; k <= 900; ++k) {
    const double t = k * 0.01;
    const bool walking = t < 6.0;
    gs.update(seconds_to_ns(t), walking ? 1.5 * std::cos(2 * M_PI * 2.0 * t) : 0.0, 0.0, walking ? 1.0 : 0.0);
    if (walking && k >= 50 && k % 50 == 30) {
      Step s;
      s.t = seconds_to_ns(t - 0.3);
      s.length_m = 0.7;
      s.interval_s = 0.5;
      gs.add_step(s);
    }
    const TimeNs tn = seconds_to_ns(t);
    if (k > 0) {
      const double v = gs.take_speed(t_prev, tn), r = gs.turn_paid_rps();
      REQUIRE(std::isfinite(r));
      CHECK(r >= 0.0);
      if (t > 2.0) {
        distance += v * 0.01;
        angle += r * 0.01;
      }
      if (t > 7.5) angle_while_still += r * 0.01;
    }
    t_prev = tn;
  }
  INFO("distance " << distance << " m, angle " << angle << " rad");
  REQUIRE(distance > 4.0);
  CHECK(angle / distance == Approx(1.0 / 1.4).epsilon(0.05));
  CHECK(angle_while_still == 0.0);
}

namespace {

// A walker who slows to a stop as the simulator's does (core/sim/gait.hpp): speed v0 g(t),
// g falling from 1 to 0 over [t_ramp, t_ramp + 1] s (a cosine), the step phase advancing
// with g, so every step covers 0.7 m however slow; bounce 1.5 g^2 m/s^2 (the acceleration
// of a bounce whose phase slows with g). Heel strikes are counted while g >= 0.5 and reported
// 0.3 s late. Returns the distance handed out at the end minus the distance walked.
double stop_overshoot(const GaitSpeedOptions& options) {
  const double period = 1.0 / 1.8, length = 0.7, v0 = length / period, t_ramp = 8.0, dt = 0.01;
  GaitSpeed gs(options);
  double phase = 0.0, walked = 0.0, last_strike = 0.0;
  int strikes = 0;
  std::vector<std::pair<double, double>> pending;  // (heel strike, interval)
  TimeNs t_prev = 0;
  for (int k = 0; k <= 1200; ++k) {
    const double t = 1.0 + k * dt;
    const double g = t < t_ramp ? 1.0 : t > t_ramp + 1.0 ? 0.0 : 0.5 * (1.0 + std::cos(M_PI * (t - t_ramp)));
    if (k > 0) {
      walked += v0 * g * dt;
      const double next = phase + g * dt / period;
      if (std::floor(next) > std::floor(phase) && g >= 0.5) {
        pending.emplace_back(t, strikes == 0 ? 0.0 : t - last_strike);
        last_strike = t;
        ++strikes;
      }
      phase = next;
    }
    gs.update(seconds_to_ns(t), 1.5 * g * g * std::cos(2 * M_PI * phase));
    while (!pending.empty() && t >= pending.front().first + 0.3) {
      Step s;
      s.t = seconds_to_ns(pending.front().first);
      s.length_m = length;
      s.interval_s = pending.front().second;
      gs.add_step(s);
      pending.erase(pending.begin());
    }
    if (k > 0) gs.take_speed(t_prev, seconds_to_ns(t));
    t_prev = seconds_to_ns(t);
  }
  // The first heel strike comes a whole step (0.7 m) into the walk: every step is 0.7 m.
  return gs.output_m() - walked;
}

}  // namespace

TEST_CASE("Gait speed does not overshoot a stop: the last step's catch-up slows with the bounce", "[imu][motion]") {
  GaitSpeedOptions full_pace;
  full_pace.catch_up_by_bounce = false;
  const double with_bounce = stop_overshoot(GaitSpeedOptions{}), at_full_pace = stop_overshoot(full_pace);
  INFO("overshoot at the stop: " << with_bounce << " m (catch-up by bounce), " << at_full_pace << " m (full pace)");
  CHECK(std::abs(with_bounce) < 0.05);
  CHECK(at_full_pace > 0.1);
  CHECK(at_full_pace - with_bounce > 0.07);
}

namespace {

// A walk, a stop and a second walk, the envelope g as in stop_overshoot (cosine ramps of 1 s:
// up over [1, 2], down over [6, 7], up again over [9, 10] s), each walk starting on a whole
// stance (phase 0), every heel strike a 0.7 m step reported 0.3 s late, the first of a walk
// without an interval and short (see below). Before a walk's first step is known MotionSource moves the walker with
// another model and then syncs GaitSpeed; from there the output must follow the walk. Returns
// the largest change of output - walked over the 2 s after the second walk's first step.
double restart_error(const GaitSpeedOptions& options) {
  const double period = 1.0 / 1.8, length = 0.7, v0 = length / period, dt = 0.01;
  const auto ramp = [](double x) { return 0.5 * (1.0 - std::cos(M_PI * std::clamp(x, 0.0, 1.0))); };
  GaitSpeed gs(options);
  double phase = 0.0, walked = 0.0, last_strike = -10.0, offset = 0.0, t_restart = 0.0, worst = 0.0;
  bool restarted = false;
  std::vector<std::pair<double, double>> pending;  // (heel strike, interval)
  TimeNs t_prev = 0;
  for (int k = 0; k <= 1200; ++k) {
    const double t = 1.0 + k * dt;
    const double g = t < 6.0 ? ramp(t - 1.0) : t < 9.0 ? 1.0 - ramp(t - 6.0) : ramp(t - 9.0);
    if (std::abs(t - 9.0) < 0.5 * dt) phase = 0.0;
    if (k > 0) {
      walked += v0 * g * dt;
      const double next = phase + g * dt / period;
      if (std::floor(next) > std::floor(phase)) {
        pending.emplace_back(t, t - last_strike > 2.0 ? 0.0 : t - last_strike);
        last_strike = t;
      }
      phase = next;
    }
    gs.update(seconds_to_ns(t), 1.5 * g * g * std::cos(2 * M_PI * phase));
    while (!pending.empty() && t >= pending.front().first + 0.3) {
      Step s;
      s.t = seconds_to_ns(pending.front().first);
      // A walk's first step is found with a small bounce: the Weinberg model (length ~ bounce^1/4)
      // makes it short. It is counted before the sync below, so it moves only the pace.
      s.length_m = pending.front().second > 0.0 ? length : 0.75 * length;
      s.interval_s = pending.front().second;
      gs.add_step(s);
      pending.erase(pending.begin());
      if (t > 9.0 && !restarted) {
        restarted = true;
        gs.sync();
        offset = gs.output_m() - walked;
        t_restart = t;
      }
    }
    if (k > 0) gs.take_speed(t_prev, seconds_to_ns(t));
    t_prev = seconds_to_ns(t);
    if (restarted && t <= t_restart + 2.0) worst = std::max(worst, std::abs(gs.output_m() - walked - offset));
  }
  return worst;
}

}  // namespace

TEST_CASE("Gait speed follows a walk that starts again: the extrapolation runs at the walking pace", "[imu][motion]") {
  GaitSpeedOptions last_step;
  last_step.extrapolate_at_reference_pace = false;
  const double reference = restart_error(GaitSpeedOptions{}), at_last_step = restart_error(last_step);
  INFO("largest error after the restart: " << reference << " m (reference pace), " << at_last_step
                                            << " m (the last step's pace)");
  CHECK(reference < 0.08);
  CHECK(at_last_step > 0.12);  // the short first step's pace, then the next step's catch-up
}
