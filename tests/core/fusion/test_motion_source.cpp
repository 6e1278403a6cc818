// MotionSource (core/fusion/motion_source.cpp): the pdr model's regimes around a stop.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <tuple>

#include "core/fusion/motion_source.hpp"
#include "core/imu/sim_walk.hpp"
#include "core/sim/imu_grade.hpp"
#include "core/sim/walk_trajectory.hpp"

using namespace luxloc;

namespace {

// What one prediction saw on the sim walk (seed 1, the stop at 61 s): its time, the regime
// before and after the input, the distance output before it, and the input.
struct Prediction {
  double t;
  MotionRegime before, after;
  double output_before;
  const MotionInput& u;
};

// Feeds the sim walk (seed 1) to `ms` up to 62.9 s with the true attitude, calling `see`
// with every prediction after the first sample.
template <class See>
void walk_to_the_stop(MotionSource& ms, See see) {
  const test::SimWalk& w = test::sim_walk(1);
  TimeNs t_prev = 0;
  bool first = true;
  for (const ImuSample& s : w.imu) {
    const double t = ns_to_seconds(s.t);
    if (t > 62.9) break;
    ms.update(s, w.simulator.truth(t).R_BtoW);
    if (!first) {
      const MotionRegime before = ms.regime();
      const double output_before = ms.gait().output_m();
      const MotionInput u = ms.input(t_prev, s.t);
      see(Prediction{t, before, ms.regime(), output_before, u});
    }
    first = false;
    t_prev = s.t;
  }
}

// The first gait -> still transition after 50 s: the walk's stop.
bool stops(const Prediction& p) {
  return p.t > 50.0 && p.before == MotionRegime::gait && p.after == MotionRegime::still;
}

}  // namespace

TEST_CASE("pdr motion: a walk's last steps are paid out after the walker stops, then nothing moves", "[motion]") {
  // The sim walk stops at 61 s for 2 s (seed 1: at 31 s little is owed). Its last steps are confirmed 0.3 s after their heel
  // strikes, when the bounce has already died: the distance they add must still reach the
  // filter (it was dropped: ~0.2 m short along the walk at every stop).
  MotionSource ms;
  bool stopped = false;
  double output_before_stop = 0.0, paid_still = 0.0, paid_late = 0.0, stop_t = 0.0;
  walk_to_the_stop(ms, [&](const Prediction& p) {
    if (!stopped && stops(p)) {
      stopped = true;
      stop_t = p.t;
      output_before_stop = p.output_before;
    }
    if (stopped && p.u.has_gait) {
      paid_still += p.u.gait.speed_mps * p.u.dt;
      if (p.t >= 62.3) paid_late += p.u.gait.speed_mps * p.u.dt;
    }
    if (stopped) CHECK_FALSE(p.u.has_acc);  // no strapdown while standing
  });
  const double owed = ms.gait().expected_m() - output_before_stop;
  INFO("stepping ended at " << stop_t << " s owing " << owed << " m; paid since " << paid_still << " m");
  REQUIRE(stopped);
  CHECK(stop_t > 60.5);
  CHECK(stop_t < 61.8);
  CHECK(ms.regime() == MotionRegime::still);
  // The case is real: the last step was confirmed after the bounce died (0.044 m owed since
  // its catch-up slows with the bounce, GaitSpeedOptions::catch_up_by_bounce; 0.2 m before).
  CHECK(owed > 0.03);
  CHECK(paid_still == Approx(owed).margin(0.005));
  CHECK(std::abs(ms.gait().output_m() - ms.gait().expected_m()) < 0.005);
  CHECK(paid_late < 0.005);  // standing still moves nothing once it is paid
}

TEST_CASE("pdr motion: what the last steps owe at a stop is paid with along-track noise of half of it", "[motion]") {
  // MotionSourceOptions::stop_owed_sigma (0.7): over the payout the along-track variance the
  // filters add (length_sigma^2 / T per second) sums to f^2 owed^2 / 2, 1 sigma ~0.5 x owed;
  // while walking the per-step noise stays the step's own (5 % of its length).
  // The along-track variance the filters add over one input: length_sigma^2 / T per second.
  const auto variance = [](const MotionInput& u) {
    return u.gait.length_sigma_m * u.gait.length_sigma_m / u.gait.step_period_s * u.dt;
  };
  // The last step's catch-up at the full pace: 0.2 m owed at this stop, so the payout's
  // noise stands out of the step's own (with the bounce-scaled catch-up 0.04 m are owed).
  MotionSourceOptions full_pace;
  full_pace.gait.catch_up_by_bounce = false;
  MotionSource ms(full_pace);
  bool stopped = false;
  double var_still = 0.0, output_before_stop = 0.0, max_walking_sigma_share = 0.0;
  walk_to_the_stop(ms, [&](const Prediction& p) {
    if (!stopped && stops(p)) {
      stopped = true;
      output_before_stop = p.output_before;
    }
    if (stopped && p.u.has_gait) var_still += variance(p.u);
    if (p.after == MotionRegime::gait && p.u.gait.speed_mps > 0.0 && ms.gait().has_step())
      max_walking_sigma_share =
          std::max(max_walking_sigma_share, p.u.gait.length_sigma_m / ms.gait().last_step().length_m);
  });
  REQUIRE(stopped);
  const double owed = ms.gait().expected_m() - output_before_stop;
  INFO("owed " << owed << " m at the stop, payout sigma " << std::sqrt(var_still) << " m");
  REQUIRE(owed > 0.1);
  // f / sqrt(2) = 0.49 of what is owed, plus (the larger of the two each instant) the step's
  // own 5 % that accrues while the servo pays.
  CHECK(std::sqrt(var_still) >= 0.45 * owed);
  CHECK(std::sqrt(var_still) <= 0.65 * owed);
  CHECK(max_walking_sigma_share == Approx(0.05).margin(1e-6));

  MotionSourceOptions none = full_pace;
  none.stop_owed_sigma = 0.0;
  MotionSource quiet(none);
  stopped = false;
  double var_quiet = 0.0;
  walk_to_the_stop(quiet, [&](const Prediction& p) {
    stopped = stopped || stops(p);
    if (stopped && p.u.has_gait) var_quiet += variance(p.u);
  });
  CHECK(var_quiet < 0.5 * var_still);  // the step's own 5 % only
}

TEST_CASE("pdr motion: a walker turning round on the spot is held in place, not integrated", "[motion][pace]") {
  // The walk scenario's walker with a 4 s stop at 40 s, turning round (180 deg in 1.5 s) in
  // it, and a turn at the very start, before any step; a consumer IMU. Strapdown moved such
  // a standing walker 0.05-0.19 m per turn (MotionSourceOptions::hold_turning_in_place).
  sim::Scenario sc = sim::make_scenario("walk");
  sim::WalkOptions w = *sc.walk;
  w.walking = {{2.0, 40.0}, {44.0, std::numeric_limits<double>::infinity()}};
  w.turns = {{0.2, 1.5, true}, {41.2, 1.5, false}};
  sc.trajectory = std::make_shared<sim::WalkTrajectory>(w);
  sim::SimOptions o;
  o.seed = 3;
  o.duration_s = 50.0;
  o.imu = sim::imu_grade("consumer");
  const sim::Simulator simulator(sc, o);
  const std::vector<ImuSample> imu = simulator.imu_samples();
  const auto run = [&](bool hold) {
    MotionSourceOptions mo;
    mo.hold_turning_in_place = hold;
    MotionSource ms(mo);
    double strapdown_in_turn = 0.0, strapdown_at_start = 0.0;
    for (std::size_t i = 0; i < imu.size(); ++i) {
      const double t = ns_to_seconds(imu[i].t);
      ms.update(imu[i], simulator.truth(t).R_BtoW);
      if (i == 0) continue;
      const MotionInput u = ms.input(imu[i - 1].t, imu[i].t);
      if (!u.has_acc) continue;
      if (t > 41.0 && t < 43.0) strapdown_in_turn += u.dt;
      if (t > 0.2 && t < 1.7) strapdown_at_start += u.dt;
    }
    return std::make_tuple(strapdown_in_turn, strapdown_at_start, ms.turning_in_place_s());
  };
  const auto [held_turn, held_start, held_s] = run(true);
  const auto [loose_turn, loose_start, loose_s] = run(false);
  INFO("held: strapdown " << held_turn << " s in the turn, " << held_start << " s at the start, held " << held_s
                          << " s; without: " << loose_turn << " s in the turn");
  CHECK(loose_turn > 1.0);  // the case is real: without the hold the turn is strapdown
  CHECK(loose_s == 0.0);
  CHECK(held_turn == 0.0);
  CHECK(held_s > 1.0);
  CHECK(held_s < 3.0);
  CHECK(held_start > 0.5);  // before any step (a robot, a trolley): strapdown as before
}
