#pragma once
// A pedestrian carrying the device in front of them: it follows a smooth closed path
// (SmoothPath) with the walking envelope and step phase of a Gait, heading along the path,
// with a vertical bounce, forward-speed modulation and roll / pitch / yaw sway per step.
// The pace may drift within the walk (GaitOptions::pace_waves: cadence, step length and
// bounce follow it), and the walker may turn round on the spot while standing (`turns`) and
// walk back the way they came, take a few side steps (`side_steps`), and hold the device
// off the body's turning axis (`lever_arm_m`).
// Every quantity is built from Jets, so velocity, acceleration and angular rate are exact.
#include <Eigen/Core>
#include <vector>

#include "core/sim/gait.hpp"
#include "core/sim/smooth_path.hpp"
#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

// A turn round on the spot (issue 12 part 1): while standing, the body turns by +-180 deg
// (a C2 smoothstep of the yaw), and the walk goes on backwards along the path.
struct TurnOnSpot {
  double start_s = 0.0;     // the envelope must be 0 over [start_s, start_s + duration_s]
  double duration_s = 1.5;  // people turn round in 1-2 s
  bool left = true;         // +180 deg (counter-clockwise seen from above) or -180 deg
};

// A few side steps (issue 12 part 1): while walking (envelope 1), the body turns by 90 deg
// against the path over ramp_s, steps sideways along it at a slower pace, and turns back.
// The path, and so the direction of travel, is that of the walk: the device's heading is
// 90 deg off the direction it moves in, which a step-and-heading model does not expect.
struct SideStep {
  double start_s = 0.0;     // the body starts turning (envelope 1 from here to the end)
  double duration_s = 3.0;  // including both turns (multiples of PaceDrift::kPanel after rounding)
  double ramp_s = 0.6;      // each turn of the body, 90 deg
  bool left = true;         // the walker moves to their left (body yaw = path heading - 90 deg)
  double slowdown = 0.5;    // fraction of the speed lost while stepping sideways (< 1)
};

struct WalkOptions {
  std::vector<Eigen::Vector2d> waypoints;  // closed polygon (world x, y)
  double corner_sigma_m = 0.5;             // turn rounding (SmoothPath sigma)
  double start_u_m = 0.0;                  // arc length along the polygon where the walk starts
  double height_m = 1.0;                   // nominal device height above the floor
  std::vector<WalkInterval> walking;       // when the person walks (else stands still)
  std::vector<TurnOnSpot> turns;           // sorted, each within a standing time
  std::vector<SideStep> side_steps;        // sorted, each within a walk's plateau
  // Where the device is held from the body's turning axis (a vertical line through the
  // walker), in the body's yaw frame: forward, left (m). A phone held in front of the chest is
  // 0.2-0.4 m forward; a turn round on the spot then carries it along a half circle. Zero: on
  // the axis (every scenario before issue 12's hand-held walker).
  Eigen::Vector2d lever_arm_m = Eigen::Vector2d::Zero();
  GaitOptions gait;
};

class WalkTrajectory final : public Trajectory {
 public:
  // Throws std::invalid_argument for a turn that is not within a standing time.
  explicit WalkTrajectory(const WalkOptions& options);
  BodyState state(double t_s) const override;
  std::vector<double> step_times(double until_s) const override { return gait_.heel_strikes(until_s); }

  const SmoothPath& path() const { return path_; }
  const Gait& gait() const { return gait_; }
  const std::vector<PaceDip>& side_steps_in_walked_time() const { return side_steps_G_; }
  // Path parameter (polygon arc length) reached at time t, with its derivatives.
  Jet path_parameter(double t_s) const;
  // The turns' yaw (+-pi each, summed) at t, with its derivatives.
  Jet turned_yaw(double t_s) const;
  // The vertical displacement of the heel-strike impacts at t (GaitOptions::heel_impact_mps2).
  Jet heel_impact(double t_s) const;
  // The side steps' yaw against the path (-+pi/2 on each plateau) at t, with its derivatives.
  Jet side_step_yaw(double t_s) const;

 private:
  WalkTrajectory(const WalkOptions& options, std::vector<PaceDip> side_steps_G);
  WalkOptions opt_;
  SmoothPath path_;
  Gait gait_;
  // After the k-th turn (k from 1): A_k - (-1)^k D(G_k), the constant of path_parameter
  // (nominal-speed seconds; A_k the signed path distance walked up to the turn).
  std::vector<double> turn_offset_s_;
  // The side steps in walked time (rounded to PaceDrift::kPanel; parallel to opt_.side_steps).
  std::vector<PaceDip> side_steps_G_;
};

}  // namespace luxloc::sim
