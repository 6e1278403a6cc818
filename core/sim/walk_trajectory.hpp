#pragma once
// A pedestrian carrying the device in front of them: it follows a smooth closed path
// (SmoothPath) with the walking envelope and step phase of a Gait, heading along the path,
// with a vertical bounce, forward-speed modulation and roll / pitch / yaw sway per step.
// Every quantity is built from Jets, so velocity, acceleration and angular rate are exact.
#include <Eigen/Core>
#include <vector>

#include "core/sim/gait.hpp"
#include "core/sim/smooth_path.hpp"
#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

struct WalkOptions {
  std::vector<Eigen::Vector2d> waypoints;  // closed polygon (world x, y)
  double corner_sigma_m = 0.5;             // turn rounding (SmoothPath sigma)
  double start_u_m = 0.0;                  // arc length along the polygon where the walk starts
  double height_m = 1.0;                   // nominal device height above the floor
  std::vector<WalkInterval> walking;       // when the person walks (else stands still)
  GaitOptions gait;
};

class WalkTrajectory final : public Trajectory {
 public:
  explicit WalkTrajectory(const WalkOptions& options);
  BodyState state(double t_s) const override;
  std::vector<double> step_times(double until_s) const override { return gait_.heel_strikes(until_s); }

  const SmoothPath& path() const { return path_; }
  const Gait& gait() const { return gait_; }
  // Path parameter (polygon arc length) reached at time t, with its derivatives.
  Jet path_parameter(double t_s) const;
  // The vertical displacement of the heel-strike impacts at t (GaitOptions::heel_impact_mps2).
  Jet heel_impact(double t_s) const;

 private:
  WalkOptions opt_;
  SmoothPath path_;
  Gait gait_;
};

}  // namespace luxloc::sim
