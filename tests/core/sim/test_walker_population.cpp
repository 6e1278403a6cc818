// The walker population of `luxloc sim --walker random` (issue 12 part 1): per-seed draws
// within the documented ranges, reproducible, and applied to the scenario's walk.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "core/sim/scenario.hpp"
#include "core/sim/walker_population.hpp"

using namespace luxloc::sim;

TEST_CASE("draw_walker: ranges of issue 12, reproducible per seed, different across seeds", "[sim][walker]") {
  std::set<long> lengths;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const WalkerDraw w = draw_walker(seed, 90.0);
    INFO("seed " << seed);
    CHECK(w.step_hz >= 1.4);
    CHECK(w.step_hz <= 2.2);
    CHECK(w.step_length_m >= 0.35 - 1e-12);
    CHECK(w.step_length_m <= 0.85);
    CHECK(w.speed_mps <= 1.8);
    CHECK(w.speed_mps == Approx(w.step_length_m * w.step_hz));
    CHECK(w.corner_sigma_m >= 0.3);
    CHECK(w.corner_sigma_m <= 1.0);
    REQUIRE_FALSE(w.walking.empty());
    CHECK(w.walking.front().start_s == 2.0);
    CHECK(std::isinf(w.walking.back().stop_s));
    for (std::size_t i = 1; i < w.walking.size(); ++i) {
      const double stop = w.walking[i].start_s - w.walking[i - 1].stop_s;
      CHECK(stop >= 1.0);
      CHECK(stop <= 10.0);
    }
    lengths.insert(std::lround(w.step_length_m * 100));
    const WalkerDraw again = draw_walker(seed, 90.0);
    CHECK(again.step_length_m == w.step_length_m);
    CHECK(again.walking.size() == w.walking.size());
  }
  CHECK(lengths.size() > 30);  // the seeds spread over the range
}

TEST_CASE("apply_walker walks the scenario's path with the drawn gait", "[sim][walker]") {
  const Scenario s = make_scenario("walk");
  REQUIRE(s.walk);
  const WalkerDraw w = draw_walker(7, 90.0);
  const WalkOptions o = apply_walker(*s.walk, w);
  CHECK(o.waypoints == s.walk->waypoints);
  CHECK(o.gait.speed_mps == w.speed_mps);
  CHECK(o.gait.step_hz == w.step_hz);
  CHECK(o.corner_sigma_m == w.corner_sigma_m);
  const WalkTrajectory t(o);
  // Heel strikes at the drawn cadence while walking (away from the stops' ramps).
  const auto strikes = t.step_times(90.0);
  REQUIRE(strikes.size() > 20);
  const double mid = 0.5 * (w.walking.front().start_s + w.walking.front().stop_s);
  std::size_t k = 0;
  while (k + 1 < strikes.size() && strikes[k] < mid) ++k;
  CHECK(strikes[k] - strikes[k - 1] == Approx(1.0 / w.step_hz).epsilon(0.02));
  CHECK_FALSE(make_scenario("static").walk);  // nothing to replace there
}

TEST_CASE("draw_fast_walker: 1.7 m/s at 1.9-2.2 Hz, the rest of the seed's walker kept", "[sim][walker]") {
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    const WalkerDraw w = draw_walker(seed, 90.0), f = draw_fast_walker(seed, 90.0);
    INFO("seed " << seed);
    CHECK(f.speed_mps == 1.7);
    CHECK(f.step_hz >= 1.9);
    CHECK(f.step_hz <= 2.2);
    CHECK(f.step_length_m == Approx(1.7 / f.step_hz));
    CHECK(f.step_length_m >= 0.77);
    CHECK(f.step_length_m <= 0.9);
    // The bounce follows the step by the population's rule, with the seed's own factor.
    if (w.bounce_m > 0.0081 && w.bounce_m < 0.0349 && f.bounce_m < 0.0349)
      CHECK(f.bounce_m / f.step_length_m == Approx(w.bounce_m / w.step_length_m));
    CHECK(f.corner_sigma_m == w.corner_sigma_m);
    CHECK(f.walking.size() == w.walking.size());
  }
}

TEST_CASE("heel impacts: ~12 g at each strike, exact derivatives, the walk unchanged around them", "[sim][walker]") {
  const Scenario s = make_scenario("walk");
  REQUIRE(s.walk);
  WalkOptions o = apply_walker(*s.walk, draw_fast_walker(3, 60.0));
  const WalkTrajectory plain(o);
  o.gait.heel_impact_mps2 = 11.0 * 9.81;
  const WalkTrajectory hit(o);
  const auto strikes = hit.step_times(60.0);
  REQUIRE(strikes.size() > 50);
  int checked = 0;
  for (const double tk : strikes) {
    if (hit.gait().envelope(tk).v < 1.0) continue;  // full steps only
    // +A at the strike on top of the walk's own acceleration.
    CHECK(hit.state(tk).a_BinW.z() - plain.state(tk).a_BinW.z() == Approx(11.0 * 9.81).epsilon(1e-6));
    // Gone 80 ms later (zero net velocity: the walk goes on where it was).
    CHECK((hit.state(tk + 0.08).p_BinW - plain.state(tk + 0.08).p_BinW).norm() < 1e-4);
    CHECK((hit.state(tk + 0.08).v_BinW - plain.state(tk + 0.08).v_BinW).norm() < 1e-3);
    // Derivatives through the spike agree with the poses (the IMU is the truth's).
    for (const double dt : {-0.02, -0.005, 0.0, 0.012, 0.03}) {
      const double t = tk + dt, h = 1e-6;
      const BodyState m = hit.state(t), a = hit.state(t - h), b = hit.state(t + h);
      CHECK(std::abs(m.v_BinW.z() - (b.p_BinW.z() - a.p_BinW.z()) / (2 * h)) < 1e-6);
      CHECK(std::abs(m.a_BinW.z() - (b.v_BinW.z() - a.v_BinW.z()) / (2 * h)) < 1e-3);
    }
    ++checked;
  }
  CHECK(checked > 40);
}

TEST_CASE("draw_walker: the pace drifts within the walk, turns round on the spot at some stops", "[sim][walker][pace]") {
  int turns = 0, stops_long = 0, sessions_with_turns = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const WalkerDraw w = draw_walker(seed, 300.0), steady = draw_steady_walker(seed, 300.0);
    INFO("seed " << seed);
    REQUIRE(w.pace_waves.size() == 2);
    double amplitude = 0.0;
    for (const PaceWave& p : w.pace_waves) {
      CHECK(p.amplitude >= 0.0);
      CHECK(p.amplitude <= 0.12);
      CHECK(p.period_s >= 30.0);
      CHECK(p.period_s <= 240.0);
      amplitude += p.amplitude;
    }
    CHECK(w.speed_mps * (1.0 + amplitude) <= 2.0 + 1e-9);  // peaks below a run
    // The steady walker is the same draw without the drift and the turns.
    CHECK(steady.pace_waves.empty());
    CHECK(steady.turns.empty());
    CHECK(steady.step_length_m == w.step_length_m);
    CHECK(steady.walking.size() == w.walking.size());
    for (std::size_t i = 0; i + 1 < w.walking.size(); ++i) stops_long += w.walking[i + 1].start_s - w.walking[i].stop_s >= 2.5;
    for (const TurnOnSpot& t : w.turns) {
      CHECK(t.duration_s >= 1.0);
      CHECK(t.duration_s <= 2.0);
      bool standing = false;  // within the standing time between two walks, >= 2.5 s long
      for (std::size_t i = 0; i + 1 < w.walking.size(); ++i)
        standing |= t.start_s >= w.walking[i].stop_s && t.start_s + t.duration_s <= w.walking[i + 1].start_s &&
                    w.walking[i + 1].start_s - w.walking[i].stop_s >= 2.5;
      CHECK(standing);
    }
    turns += static_cast<int>(w.turns.size());
    sessions_with_turns += !w.turns.empty();
    // The drawn walk is a valid trajectory (turns within standing times, drift within range).
    const Scenario s = make_scenario("walk");
    if (seed <= 5) CHECK_NOTHROW(WalkTrajectory(apply_walker(*s.walk, w)).state(299.0));
  }
  // A third of the long stops turn round.
  CHECK(turns > stops_long / 5);
  CHECK(turns < stops_long / 2);
  CHECK(sessions_with_turns > 100);
  CHECK(draw_fast_walker(3, 90.0).pace_waves.empty());
}

TEST_CASE("draw_walker: side steps in half the walks, the device held off the turning axis", "[sim][walker]") {
  int walks = 0, side_steps = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const WalkerDraw w = draw_walker(seed, 300.0), turning = draw_turning_walker(seed, 300.0);
    INFO("seed " << seed);
    walks += static_cast<int>(w.walking.size());
    side_steps += static_cast<int>(w.side_steps.size());
    for (const SideStep& s : w.side_steps) {
      CHECK(s.duration_s >= 2.0);
      CHECK(s.duration_s <= 4.0);
      CHECK(s.ramp_s >= 0.6);
      CHECK(s.ramp_s <= 1.0);
      CHECK(s.slowdown >= 0.3);
      CHECK(s.slowdown <= 0.6);
    }
    CHECK(w.lever_arm_m.x() >= 0.0);
    CHECK(w.lever_arm_m.x() <= 0.4);
    CHECK(std::abs(w.lever_arm_m.y()) <= 0.2);
    // The turning walker is the stop-28 draw: the same walks, drift and turns, without them.
    CHECK(turning.side_steps.empty());
    CHECK(turning.lever_arm_m.isZero());
    CHECK(turning.turns.size() == w.turns.size());
    CHECK(turning.pace_waves[0].amplitude == w.pace_waves[0].amplitude);
    CHECK(draw_steady_walker(seed, 300.0).side_steps.empty());
    const Scenario s = make_scenario("walk");
    if (seed <= 5) CHECK_NOTHROW(WalkTrajectory(apply_walker(*s.walk, w)).state(299.0));
  }
  // Half the walks long enough take side steps (most walks are: 10-30 s).
  CHECK(side_steps > walks / 3);
  CHECK(side_steps < walks * 6 / 10);
}

