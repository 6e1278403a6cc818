#pragma once
// Where the device is held from its holder's turning axis (issue 12 part 1: a phone held in
// front of the chest, a device in a trouser pocket), learnt from turns on the spot.
//
// A walker turning on the spot turns about a vertical axis through the body; a device held
// at l (forward, left, in the body's yaw frame) moves on a circle round it:
//   p = c + R(psi) l,   p'' = (psi'' J - psi'^2 I) R(psi) l = M l
// (J the 90 deg rotation), with c fixed. Its horizontal acceleration in the world is thus
// linear in l, and l is the least-squares solution over the turn's samples. M^T M =
// (psi''^2 + psi'^4) I, so every turn observes both components alike. A turn is taken when
// it excites enough (int (psi''^2 + psi'^4) dt >= min_excitation) and the fit explains the
// acceleration (1 - residual / energy >= min_fit); its normal equations join the earlier
// turns'. Once learnt, every change of heading moves the device by (R(psi1) - R(psi0)) l on
// top of the body's own motion: round a corner, and round the turn itself (held in place,
// not integrated by strapdown).
#include <Eigen/Core>
#include <optional>

#include "core/common/time.hpp"

namespace luxloc {

struct LeverArmOptions {
  // A turn on the spot: the yaw rate above this (smoothed over rate_tau_s). 1 rad/s: a
  // person turns round in 1-2 s (180 deg: 1.6-3.1 rad/s mean); a stop's sway stays far below.
  double min_rate_rps = 1.0;
  double rate_tau_s = 0.02;  // the rate's smoothing before it is differentiated
  // A 90 deg turn in 1.5 s gives ~15 s^-3; a 180 deg turn in 2 s ~60. 10: half a quick
  // quarter turn, enough for ~1 cm at 0.2 m/s^2 of acceleration noise (tilt leakage).
  double min_excitation = 10.0;
  double min_fit = 0.6;      // share of the turn's acceleration the rigid turn explains
  double max_length_m = 0.6; // an arm's reach: past it the fit saw something else
};

class LeverArm {
 public:
  explicit LeverArm(const LeverArmOptions& options = {});

  // One sample while the walker stands (no steps, no bounce) and may turn: its time, the
  // device yaw (rad, ENU), the yaw rate about the world vertical and the horizontal
  // acceleration in the world (gravity removed).
  void update_standing(TimeNs t, double yaw_rad, double yaw_rate_rps, const Eigen::Vector2d& a_inW);
  // Walking or moving: a turn in progress ends here (and is fitted).
  void interrupt();

  bool turning() const { return turning_; }
  // The lever arm (forward, left; m), once a turn gave it.
  const std::optional<Eigen::Vector2d>& lever() const { return lever_; }
  int turns_used() const { return turns_used_; }
  int turns_refused() const { return turns_refused_; }
  // Where the device lies from the axis at yaw psi, in the world (0 until learnt).
  Eigen::Vector2d offset_inW(double yaw_rad) const;

 private:
  void finish_turn();

  LeverArmOptions options_;
  bool have_t_ = false, turning_ = false;
  TimeNs t_last_ = 0;
  double rate_ = 0.0;  // smoothed yaw rate
  // This turn's and all accepted turns' normal equations: N = n I, b, and the energy e.
  double turn_n_ = 0.0, turn_e_ = 0.0, all_n_ = 0.0;
  Eigen::Vector2d turn_b_ = Eigen::Vector2d::Zero(), all_b_ = Eigen::Vector2d::Zero();
  std::optional<Eigen::Vector2d> lever_;
  int turns_used_ = 0, turns_refused_ = 0;
};

}  // namespace luxloc
