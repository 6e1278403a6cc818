#pragma once
// The kidnapped robot problem (issue 14): at `start_s` the device is picked up, its camera
// covered, and carried `distance_m` (straight-line distance) to a place further along its
// own walk, where it is put down and the walk goes on from there. The carry is smooth (a
// minimum-jerk profile, no steps: in a bag or a cart), so dead reckoning sees no walking
// and the filter's belief stays where the device was picked up.
#include <memory>
#include <vector>

#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

struct KidnapOptions {
  double start_s = 0.0;
  double distance_m = 20.0;  // at least this far from the pick-up point (horizontal)
  double speed_mps = 1.0;    // mean speed of the carry (peak 1.875x: minimum jerk)
};

class KidnapTrajectory final : public Trajectory {
 public:
  // Throws std::invalid_argument when the walk never gets distance_m away from the pick-up
  // point within an hour after it.
  KidnapTrajectory(std::shared_ptr<const Trajectory> base, const KidnapOptions& options);
  BodyState state(double t_s) const override;
  std::vector<double> step_times(double until_s) const override;

  double start_s() const { return opt_.start_s; }
  double end_s() const { return opt_.start_s + carry_s_; }  // put down: the camera sees again
  // Walk time skipped: after end_s the device is where the walk would be at t + skip_s.
  double skip_s() const { return skip_s_ - carry_s_; }
  const BodyState& pick_up() const { return from_; }
  const BodyState& put_down() const { return to_; }

 private:
  std::shared_ptr<const Trajectory> base_;
  KidnapOptions opt_;
  double carry_s_ = 0.0;  // duration of the carry
  double skip_s_ = 0.0;   // base time from pick-up to put-down
  BodyState from_, to_;
};

}  // namespace luxloc::sim
