#pragma once
// A pedestrian carrying the device in front of them: it follows a smooth closed path
// (SmoothPath) with the walking envelope and step phase of a Gait, heading along the path,
// with a vertical bounce, forward-speed modulation and roll / pitch / yaw sway per step.
// The pace may drift within the walk (GaitOptions::pace_waves: cadence, step length and
// bounce follow it), and the walker may turn round on the spot while standing (`turns`) and
// walk back the way they came.
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

struct WalkOptions {
  std::vector<Eigen::Vector2d> waypoints;  // closed polygon (world x, y)
  double corner_sigma_m = 0.5;             // turn rounding (SmoothPath sigma)
  double start_u_m = 0.0;                  // arc length along the polygon where the walk starts
  double height_m = 1.0;                   // nominal device height above the floor
  std::vector<WalkInterval> walking;       // when the person walks (else stands still)
  std::vector<TurnOnSpot> turns;           // sorted, each within a standing time
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
  // Path parameter (polygon arc length) reached at time t, with its derivatives.
  Jet path_parameter(double t_s) const;
  // The turns' yaw (+-pi each, summed) at t, with its derivatives.
  Jet turned_yaw(double t_s) const;
  // The vertical displacement of the heel-strike impacts at t (GaitOptions::heel_impact_mps2).
  Jet heel_impact(double t_s) const;

 private:
  WalkOptions opt_;
  SmoothPath path_;
  Gait gait_;
  // After the k-th turn (k from 1): A_k - (-1)^k D(G_k), the constant of path_parameter
  // (nominal-speed seconds; A_k the signed path distance walked up to the turn).
  std::vector<double> turn_offset_s_;
};

}  // namespace luxloc::sim
