#pragma once
// A population of walkers (issue 12, part 1): `luxloc sim --walker random` replaces the
// scenario's one walker by one drawn from the session's seed, so accuracy is measured on
// walkers the filter's constants were not fitted to. Drawn per session and written to
// sim_truth.yaml (`walker:`), so a failing session can be reproduced and understood:
//   step length 0.35-0.85 m and cadence 1.4-2.2 Hz (speed = length x cadence, capped at
//   1.8 m/s: issue 12's ranges), corner rounding 0.3-1.0 m (sharp to sweeping turns),
//   speed modulation per step 5-20 %, vertical bounce 1.5 cm x (step / 0.69 m) x 0.7-1.3
//   (0.8-3.5 cm: it grows with the step), sway 0.5-2x the default,
//   stops of 1-10 s every 10-30 s of walking, the pace drifting within the session (two slow
//   waves of the speed, 30-90 s and 90-240 s of walking, 0-12 % each, peaks capped at 2 m/s;
//   cadence and step length share it, core/sim/pace_drift.hpp), and a turn round on the spot
//   (1-2 s) at a third of the stops that leave >= 2.5 s of standing, the walk going on back
//   the way it came; side steps (2-4 s, the body 90 deg off the path, slowed by 30-60 %) in
//   half the walks, and the device held 0-0.4 m in front of the body's turning axis and up to
//   0.2 m to a side (a phone in the hand, a trouser pocket), so turns carry it round.
// Not drawn (yet): a device swinging in the hand (an arm's pendulum).
#include <cstdint>
#include <vector>

#include "core/sim/walk_trajectory.hpp"

namespace luxloc::sim {

struct WalkerDraw {
  double step_length_m = 0.0;
  double step_hz = 0.0;
  double speed_mps = 0.0;
  double corner_sigma_m = 0.0;
  double speed_modulation = 0.0;
  double bounce_m = 0.0;
  double sway_scale = 1.0;
  std::vector<WalkInterval> walking;
  std::vector<PaceWave> pace_waves;  // the speed's drift (none for the fast walker)
  double pace_horizon_s = 3600.0;    // the walked time the drift must cover
  std::vector<TurnOnSpot> turns;     // turns round on the spot (none for the fast walker)
  std::vector<SideStep> side_steps;  // side steps (none for the steady and fast walkers)
  Eigen::Vector2d lever_arm_m = Eigen::Vector2d::Zero();  // forward, left of the turning axis
};

inline constexpr const char* kWalkerNames[] = {"default", "random", "steady", "fast", "turning"};

// The walker of session `seed` over `duration_s` (the first 2 s standing, as every walk).
WalkerDraw draw_walker(std::uint64_t seed, double duration_s);
// The walker of draw_walker(seed) held at its drawn pace, turning only with the path, the
// device on the turning axis: the population before the drift, the turns on the spot, the
// side steps and the lever arm were drawn (stop 28, 29), kept so that a test can hold one
// diagnosed situation of those sessions.
WalkerDraw draw_steady_walker(std::uint64_t seed, double duration_s);
// The walker of draw_walker(seed) as it was drawn at stop 28: drifting and turning round on
// the spot, without side steps and with the device on the turning axis (tests pinned to a
// situation of those sessions).
WalkerDraw draw_turning_walker(std::uint64_t seed, double duration_s);
// A fast walker (issue 12: "fast walking (1.7 m/s, 12 g peaks) keeps its step length"): the
// walker of draw_walker(seed) at 1.7 m/s, cadence 1.9-2.2 Hz (steps of 0.77-0.89 m), its
// bounce grown with the step by the same rule; held at that pace (no drift) and turning only
// with the path, so the figure is the step length at 1.7 m/s.
WalkerDraw draw_fast_walker(std::uint64_t seed, double duration_s);
// `base` (a scenario's walk: its path and height) walked by `w`.
WalkOptions apply_walker(WalkOptions base, const WalkerDraw& w);

}  // namespace luxloc::sim
