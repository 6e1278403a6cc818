#include "core/sim/walker_population.hpp"

#include <algorithm>
#include <limits>
#include <numbers>
#include <random>

#include "core/sim/seeding.hpp"

namespace luxloc::sim {
namespace {

constexpr double kBouncePerStep = 0.015 / 0.694;  // the default walker's 1.5 cm at 0.694 m steps

double bounce_for_step(double step_length_m, double person) {
  return std::clamp(kBouncePerStep * step_length_m * person, 0.008, 0.035);
}

}  // namespace

WalkerDraw draw_walker(std::uint64_t seed, double duration_s) {
  std::mt19937_64 rng = make_rng(seed, RandomStream::walker);
  const auto uniform = [&rng](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  WalkerDraw w;
  w.step_hz = uniform(1.4, 2.2);
  w.step_length_m = uniform(0.35, 0.85);
  // 1.8 m/s: a brisk walk; faster is running, which the gait model does not claim.
  w.speed_mps = std::min(1.8, w.step_length_m * w.step_hz);
  w.step_length_m = w.speed_mps / w.step_hz;
  w.corner_sigma_m = uniform(0.3, 1.0);
  w.speed_modulation = uniform(0.05, 0.20);
  // The vertical bounce grows with the step: the default walker's 1.5 cm at 0.69 m steps,
  // in proportion to the step, times a person-to-person factor 0.7-1.3, at least 0.8 cm (a
  // hand-held device bounces with the arm as well). Drawn apart from the step, a 0.35 m step
  // could bounce like a 0.8 m one, which no step-length model can follow; with the square of
  // the step (an inverted pendulum) short steps fell below any step detector's threshold.
  w.bounce_m = bounce_for_step(w.step_length_m, uniform(0.7, 1.3));
  w.sway_scale = uniform(0.5, 2.0);
  // Stand 2 s, then walks of 10-30 s separated by stops of 1-10 s (standing time between
  // the ramps), the last walk to the end.
  double t = 2.0;
  while (true) {
    const double walk = uniform(10.0, 30.0);
    if (t + walk + 12.0 >= duration_s) {
      w.walking.push_back({t, std::numeric_limits<double>::infinity()});
      break;
    }
    w.walking.push_back({t, t + walk});
    t += walk + uniform(1.0, 10.0);
  }
  // Drawn after the walks, so the walker's earlier draws are those of the sessions before the
  // drift and the turns existed (stop 28).
  // The pace drifts within the walk: two slow waves of the speed in walked time, a shorter
  // one (30-90 s: a person hurrying up or dawdling) and a longer one (90-240 s: tiring,
  // settling in), 0-12 % each, so the speed spans up to +-24 % of the drawn mean. Peaks are
  // capped at 2 m/s: past that people run.
  const double period1 = uniform(30.0, 90.0), period2 = uniform(90.0, 240.0);
  double a1 = uniform(0.0, 0.12), a2 = uniform(0.0, 0.12);
  const double headroom = 2.0 / w.speed_mps - 1.0;
  const double scale = a1 + a2 > headroom ? headroom / (a1 + a2) : 1.0;
  a1 *= scale;
  a2 *= scale;
  w.pace_horizon_s = duration_s + 120.0;  // the walked time never exceeds the time (with margin for queries past the end)
  w.pace_waves = {{a1, period1, uniform(0.0, 2.0 * std::numbers::pi)}, {a2, period2, uniform(0.0, 2.0 * std::numbers::pi)}};
  // Turns round on the spot: at a third of the stops with >= 2.5 s of standing, 1-2 s long
  // (a person turning round takes 1-2 s), centred in the standing time, either way round.
  for (std::size_t i = 0; i + 1 < w.walking.size(); ++i) {
    const double standing = w.walking[i + 1].start_s - w.walking[i].stop_s;
    const double p = uniform(0.0, 1.0), duration = uniform(1.0, 2.0), left = uniform(0.0, 1.0);
    if (standing >= 2.5 && p < 1.0 / 3.0)
      w.turns.push_back({w.walking[i].stop_s + 0.5 * (standing - duration), duration, left < 0.5});
  }
  // Drawn after the turns (stop 29), so the sessions keep their walks, drift and turns.
  // Side steps in half the walks: 2-4 s (3-8 steps at 1.4-2.2 Hz), the body turning 90 deg in
  // 0.6-1.0 s (150-250 deg/s at the peak, a quick but ordinary turn of the shoulders), the pace
  // down by 30-60 % (people step sideways at 0.5-0.9 m/s), 1 s clear of the walk's ramps.
  const double ramp = GaitOptions{}.ramp_s;
  for (const WalkInterval& walk : w.walking) {
    const double from = walk.start_s + ramp + 1.0, to = std::min(walk.stop_s, duration_s) - ramp - 1.0;
    const double p = uniform(0.0, 1.0), duration = uniform(2.0, 4.0), where = uniform(0.0, 1.0);
    const double turn = uniform(0.6, 1.0), left = uniform(0.0, 1.0), slowdown = uniform(0.3, 0.6);
    if (p < 0.5 && to - from >= duration)
      w.side_steps.push_back({from + where * (to - from - duration), duration, turn, left < 0.5, slowdown});
  }
  // Where the device is held: 0-0.4 m in front of the turning axis (a trouser pocket to a
  // phone held out in front), up to 0.2 m to either side.
  w.lever_arm_m = {uniform(0.0, 0.4), uniform(-0.2, 0.2)};
  return w;
}

WalkerDraw draw_turning_walker(std::uint64_t seed, double duration_s) {
  WalkerDraw w = draw_walker(seed, duration_s);
  w.side_steps.clear();
  w.lever_arm_m.setZero();
  return w;
}

WalkerDraw draw_steady_walker(std::uint64_t seed, double duration_s) {
  WalkerDraw w = draw_turning_walker(seed, duration_s);
  w.pace_waves.clear();
  w.turns.clear();
  return w;
}

WalkerDraw draw_fast_walker(std::uint64_t seed, double duration_s) {
  WalkerDraw w = draw_steady_walker(seed, duration_s);
  // The cadence keeps its place in the drawn range (1.4-2.2 Hz -> 1.9-2.2 Hz): people walk
  // faster mostly by longer steps, and 1.7 m/s at 1.9-2.2 Hz is 0.77-0.89 m a step.
  const double person = w.bounce_m / (kBouncePerStep * w.step_length_m);
  w.step_hz = 1.9 + (w.step_hz - 1.4) * (0.3 / 0.8);
  w.speed_mps = 1.7;
  w.step_length_m = w.speed_mps / w.step_hz;
  w.bounce_m = bounce_for_step(w.step_length_m, std::clamp(person, 0.7, 1.3));
  return w;
}

WalkOptions apply_walker(WalkOptions base, const WalkerDraw& w) {
  base.corner_sigma_m = w.corner_sigma_m;
  base.walking = w.walking;
  base.turns = w.turns;
  base.side_steps = w.side_steps;
  base.lever_arm_m = w.lever_arm_m;
  GaitOptions& g = base.gait;
  g.speed_mps = w.speed_mps;
  g.step_hz = w.step_hz;
  g.speed_modulation = w.speed_modulation;
  g.pace_waves = w.pace_waves;
  g.pace_horizon_s = w.pace_horizon_s;
  g.bounce_m = w.bounce_m;
  g.roll_sway_rad *= w.sway_scale;
  g.pitch_sway_rad *= w.sway_scale;
  g.yaw_sway_rad *= w.sway_scale;
  return base;
}

}  // namespace luxloc::sim
