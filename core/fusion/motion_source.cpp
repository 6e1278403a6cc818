#include "core/fusion/motion_source.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

const char* motion_regime_name(MotionRegime r) {
  switch (r) {
    case MotionRegime::gait: return "walking";
    case MotionRegime::strapdown: return "moving";
    case MotionRegime::still: return "still";
    case MotionRegime::cv: break;
  }
  return "constant-velocity";
}

MotionSource::MotionSource(const MotionSourceOptions& options)
    : options_(options),
      pdr_(options.pdr),
      gait_(options.gait, options.pdr.detector.min_interval_s),
      still_(options.still),
      gate_(options.gate),
      lever_(options.lever) {}

void MotionSource::update(const ImuSample& s, const Eigen::Matrix3d& R_BtoW) {
  if (!s.acc_inB.allFinite() || !R_BtoW.allFinite()) return;
  const Eigen::Vector3d a_inW = R_BtoW * s.acc_inB - Eigen::Vector3d(0, 0, options_.gravity);
  if (!a_inW.allFinite()) return;
  acc_inW_ = a_inW.head<2>();
  valid_ = true;
  if (options_.model != MotionModel::pdr) return;
  still_.update(s);
  pdr_.update(s, R_BtoW);
  // Heading alpha from the attitude now (the step's own mean heading comes a step late).
  device_yaw_ = std::atan2(R_BtoW(1, 0), R_BtoW(0, 0));
  heading_rad_ = device_yaw_ + options_.pdr.heading_offset_rad;
  const double a_along = a_inW.x() * std::cos(heading_rad_) + a_inW.y() * std::sin(heading_rad_);
  // Yaw rate: the body rate about the world vertical.
  const double yaw_rate = (R_BtoW * s.gyro_inB).z();
  yaw_rate_ = yaw_rate;
  // Turns on the spot teach the lever arm: a walker (steps seen, the gait confirmed) standing.
  if (options_.lever_arm && steps_used_ > 0 && gait_confirmed() && !gait_.stepping() && !gait_.walking())
    lever_.update_standing(s.t, device_yaw_, yaw_rate, a_inW.head<2>());
  else
    lever_.interrupt();
  // The vertical acceleration the step detector saw (heel-strike impacts replaced).
  gait_.update(s.t, pdr_.vertical_mps2(), a_along, yaw_rate);
  while (const std::optional<Step> step = pdr_.pop_step()) {
    if (gait_confirmed()) {
      gait_.add_step(*step);
      ++steps_used_;
      continue;
    }
    if (!(step->interval_s > 0.0)) held_.clear();
    held_.push_back(*step);
    if (gate_.add(step->interval_s, step->swing_mps2)) {
      for (const Step& h : held_) gait_.add_step(h);  // the run of steps that proved the gait
      steps_used_ += held_.size();
      held_.clear();
    } else if (held_.size() > options_.gate.steps) {
      held_.erase(held_.begin());
    }
  }
}

MotionInput MotionSource::input(TimeNs t0, TimeNs t1) {
  MotionInput u = input_for(t0, t1);
  if (valid_ && u.dt > 0.0) regime_s_[static_cast<std::size_t>(regime_)] += u.dt;
  // The device swings round the body's axis as the heading turns (walking or standing; the
  // strapdown regime integrates the device's own acceleration, which holds it already).
  if (valid_ && lever_.lever() && input_yaw_ && (regime_ == MotionRegime::gait || regime_ == MotionRegime::still))
    u.shift_inW = lever_.offset_inW(device_yaw_) - lever_.offset_inW(*input_yaw_);
  if (valid_) input_yaw_ = device_yaw_;
  return u;
}

MotionInput MotionSource::input_for(TimeNs t0, TimeNs t1) {
  MotionInput u;
  u.dt = ns_to_seconds(t1 - t0);
  if (!valid_) return u;  // no IMU yet: constant velocity
  switch (options_.model) {
    case MotionModel::cv:
      regime_ = MotionRegime::cv;
      break;
    case MotionModel::strapdown:
      u.has_acc = true;
      u.acc_inW = acc_inW_;
      regime_ = MotionRegime::strapdown;
      break;
    case MotionModel::pdr: {
      const bool stepping = gait_.stepping();
      if (stepping) t_last_stepping_ = t1;
      // Strapdown between steps: bouncing before the first step of a walk is detected, or
      // moving without a bounce (not just after a walk: the walker is stopping then).
      // Held too when the lever arm is known and the device swings round it: the shift moves it.
      const bool turning_in_place = options_.hold_turning_in_place && !still_.still() &&
                                    (still_.force_steady() || (lever_.lever() && lever_.turning())) &&
                                    steps_used_ > 0 && gait_confirmed();
      const bool moving = gait_.walking() || (!still_.still() && !turning_in_place &&
                                              ns_to_seconds(t1 - t_last_stepping_) > options_.settle_s);
      if (turning_in_place && !moving && !stepping) turning_in_place_s_ += u.dt;
      if (!stepping && moving && options_.strapdown_between_steps) {
        u.has_acc = true;  // moving without steps: strapdown
        u.acc_inW = acc_inW_;
        gait_.sync();
        regime_ = MotionRegime::strapdown;
        break;
      }
      // Walking (gait speed), or standing still. Coming from strapdown (or cv), the
      // distance up to t0 is already covered: no catch-up for it. Standing still after a
      // walk, the servo still pays out what the walk's last steps owe: they are confirmed
      // 0.3 s after their heel strikes, often after the bounce has died (dropping it lost
      // ~0.2 m along the walk at every stop).
      if (regime_ != MotionRegime::gait && regime_ != MotionRegime::still) gait_.sync();
      regime_ = stepping ? MotionRegime::gait : MotionRegime::still;
      u.has_gait = true;
      const double owed_m = std::max(0.0, gait_.expected_m() - gait_.output_m());
      u.gait.speed_mps = gait_.take_speed(t0, t1);
      u.gait.heading_rad = heading_rad_;
      u.gait.step_period_s = gait_.step_period_s();
      u.gait.turn_rate_rps = yaw_rate_;
      u.gait.turn_paid_rps = gait_.turn_paid_rps();
      // Per-step noise only while walking (standing still has no step to be wrong about).
      if (u.gait.speed_mps > 0.0 && gait_.has_step()) {
        u.gait.length_sigma_m = gait_.last_step().length_sigma_m;
        u.gait.heading_sigma_rad = gait_.last_step().heading_sigma_rad;
      }
      // Stopped, paying out what the last steps owe: as uncertain as the owed distance
      // (MotionSourceOptions::stop_owed_sigma); the PF and EKF add length_sigma^2 / T per s.
      if (!stepping && u.gait.speed_mps > 0.0 && owed_m > 0.0 && options_.stop_owed_sigma > 0.0) {
        const double sigma =
            options_.stop_owed_sigma * std::sqrt(owed_m * u.gait.speed_mps * std::max(u.gait.step_period_s, 0.05));
        u.gait.length_sigma_m = std::max(u.gait.length_sigma_m, sigma);
      }
      break;
    }
  }
  return u;
}

}  // namespace luxloc
