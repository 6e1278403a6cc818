#include "core/imu/gait_speed.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace luxloc {

GaitSpeed::GaitSpeed(const GaitSpeedOptions& options, double confirmation_delay_s)
    : options_(options), confirmation_delay_s_(confirmation_delay_s), period_s_(options.nominal_step_s) {}

double GaitSpeed::bounce_rms() const {
  if (bounce_.empty()) return 0.0;
  return std::sqrt(std::max(0.0, bounce_sum2_) / static_cast<double>(bounce_.size()));
}

bool GaitSpeed::walking() const { return bounce_rms() >= options_.bounce_rms_mps2; }

double GaitSpeed::rate_factor() const {
  if (!options_.scale_by_bounce || !(bounce_ref_ > 0.0)) return 1.0;
  return std::clamp(bounce_rms() / bounce_ref_, 0.0, 1.0);
}

double GaitSpeed::extrapolation_pace() const {
  return options_.extrapolate_at_reference_pace && pace_ref_ > 0.0 ? pace_ref_ : speed_mps_;
}

double GaitSpeed::turn_factor() const {
  if (!(options_.turn_slowdown_s_per_rad > 0.0)) return 1.0;
  return std::clamp(1.0 - options_.turn_slowdown_s_per_rad * abs_yaw_rate_, options_.min_turn_factor, 1.0);
}

double GaitSpeed::turn_integral_at(TimeNs t, double TurnMark::*field) const {
  if (turn_history_.empty()) return 0.0;
  if (t <= turn_history_.front().t) return turn_history_.front().*field;
  for (std::size_t i = turn_history_.size(); i-- > 1;) {
    const TurnMark& m1 = turn_history_[i];
    const TurnMark& m0 = turn_history_[i - 1];
    if (m0.t <= t && t <= m1.t)
      return m0.*field + (m1.*field - m0.*field) * ns_to_seconds(t - m0.t) / std::max(ns_to_seconds(m1.t - m0.t), 1e-9);
  }
  return turn_history_.back().*field;
}

void GaitSpeed::update(TimeNs t, double a_up_mps2, double a_along_mps2, double yaw_rate_rps) {
  if (!std::isfinite(a_up_mps2) || (have_t_ && t <= t_)) return;
  if (!std::isfinite(a_along_mps2)) a_along_mps2 = 0.0;
  if (!std::isfinite(yaw_rate_rps)) yaw_rate_rps = 0.0;
  // The first sample has no interval: dt = 0 leaves the averages and integrals as they are.
  const double dt = have_t_ ? ns_to_seconds(t - t_) : 0.0;
  const double dt_capped = std::min(dt, 0.2);  // a gap in the data is not walked through
  abs_yaw_rate_ += std::min(1.0, dt / std::max(options_.turn_window_s, 1e-3)) * (std::abs(yaw_rate_rps) - abs_yaw_rate_);
  turn_integral_ += turn_factor() * dt_capped;
  abs_turn_integral_ += abs_yaw_rate_ * dt_capped;
  bounce_.emplace_back(t, a_up_mps2);
  bounce_sum2_ += a_up_mps2 * a_up_mps2;
  const TimeNs w = seconds_to_ns(options_.bounce_window_s);
  while (bounce_.size() > 1 && t - bounce_.front().first > w) {
    bounce_sum2_ -= bounce_.front().second * bounce_.front().second;
    bounce_.pop_front();
  }
  pace_integral_ += rate_factor() * turn_factor() * dt_capped;
  turn_history_.push_back(TurnMark{t, turn_integral_, abs_turn_integral_, pace_integral_});
  while (turn_history_.size() > 2 && t - turn_history_.front().t > seconds_to_ns(4.0)) turn_history_.pop_front();
  t_ = t;
  have_t_ = true;
  if (!extrapolating_) {
    accel_speed_mps_ = 0.0;
    return;
  }
  if (options_.accel_blend_tau_s > 0.0 && dt > 0.0 && dt < 0.2) {
    if (options_.accel_mean_tau_s > 0.0) {
      const double mean_w = std::min(1.0, dt / std::max(options_.accel_mean_tau_s, dt));
      accel_mean_mps2_ += mean_w * (a_along_mps2 - accel_mean_mps2_);
    }
    accel_speed_mps_ += (a_along_mps2 - accel_mean_mps2_) * dt - accel_speed_mps_ * dt / options_.accel_blend_tau_s;
  }
  // A walker who stopped bouncing stopped walking; a step not followed by another within
  // the horizon was the last.
  const double horizon = period_s_ + confirmation_delay_s_ + options_.extrapolation_margin_s;
  if (!walking() || ns_to_seconds(t - last_.t) > horizon) {
    extrapolating_ = false;
    return;
  }
  extrapolated_m_ += extrapolation_pace() * rate_factor() * turn_factor() * dt;
  extrapolated_turn_ += abs_yaw_rate_ * rate_factor() * dt;
}

void GaitSpeed::add_step(const Step& step) {
  if (!std::isfinite(step.length_m) || step.length_m <= 0.0) return;
  period_s_ = step.interval_s > 0.0 ? step.interval_s : options_.nominal_step_s;
  // A turning step is shorter: its length times the mean turn factor over the step.
  const TimeNs t_from = step.t - seconds_to_ns(period_s_);
  const double span = ns_to_seconds(step.t - t_from);
  const double factor_span = turn_integral_at(step.t, &TurnMark::factor) - turn_integral_at(t_from, &TurnMark::factor);
  const double mean_turn = span > 0.0 ? std::clamp(factor_span / span, options_.min_turn_factor, 1.0) : 1.0;
  steps_m_ += step.length_m * (options_.turn_slowdown_s_per_rad > 0.0 ? mean_turn : 1.0);
  // The angle this step turned, and what the walk turned since its heel strike.
  const double angle_at_step = turn_integral_at(step.t, &TurnMark::angle);
  steps_turn_ += std::max(0.0, angle_at_step - turn_integral_at(t_from, &TurnMark::angle));
  extrapolated_turn_ = std::max(0.0, abs_turn_integral_ - angle_at_step);
  speed_mps_ = std::min(step.length_m / period_s_, options_.max_speed_mps);
  // The walking pace: the median of the last paces, so that one step's odd interval (a
  // walk's first, a spurious detection) does not carry into the next steps.
  recent_paces_.push_back(speed_mps_);
  while (recent_paces_.size() > static_cast<std::size_t>(std::max(options_.pace_median_steps, 1)))
    recent_paces_.pop_front();
  std::vector<double> sorted(recent_paces_.begin(), recent_paces_.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  pace_ref_ = sorted[sorted.size() / 2];
  last_ = step;
  have_step_ = true;
  // The walk since this heel strike, at the walking pace scaled by the bounce since then
  // (GaitSpeedOptions::catch_up_by_bounce), as the extrapolation is.
  extrapolated_m_ = options_.catch_up_by_bounce
                        ? extrapolation_pace() * std::max(0.0, pace_integral_ - turn_integral_at(step.t, &TurnMark::pace))
                        : speed_mps_ * std::max(0.0, ns_to_seconds(t_ - step.t));
  extrapolating_ = true;
  const double rms = bounce_rms();
  bounce_ref_ = bounce_ref_ > 0.0 ? (1.0 - options_.bounce_ref_weight) * bounce_ref_ + options_.bounce_ref_weight * rms
                                  : rms;
}

double GaitSpeed::take_speed(TimeNs t0, TimeNs t1) {
  const double dt = ns_to_seconds(t1 - t0);
  turn_paid_rps_ = 0.0;
  if (!(dt > 0.0) || !have_t_) return 0.0;
  // The extrapolation's current rate, plus the servo onto the expected distance.
  const double rate = extrapolating_ ? extrapolation_pace() * rate_factor() : 0.0;
  const double tau = std::max(options_.servo_tau_s, dt);
  const double v = std::clamp(rate + (expected_m() - output_m_) / tau, 0.0, options_.max_speed_mps);
  output_m_ += v * dt;
  // The turned angle goes with the distance it was turned over: a sizeable distance still
  // owed (a confirmed step's, paid out after it, often while the walker stops) carries the
  // angle still owed with it; otherwise the distance is the extrapolation's, at the current
  // turn per metre. Two servos of their own would pay a stop's last turning step's angle
  // before its distance, and the distance then without its slowdown.
  const double owed_m = expected_m() - (output_m_ - v * dt), owed_turn = expected_turn() - output_turn_;
  double per_m = 0.0;
  if (owed_m > options_.turn_owed_min_m)
    per_m = owed_turn / owed_m;
  else if (extrapolating_)
    per_m = abs_yaw_rate_ / std::max(speed_mps_, options_.turn_min_pace_mps);
  turn_paid_rps_ = v * std::clamp(per_m, 0.0, options_.max_turn_per_m);
  output_turn_ += turn_paid_rps_ * dt;
  // The accelerometer's share is not part of the distance the servo accounts for.
  return std::clamp(v + (extrapolating_ ? accel_speed_mps_ : 0.0), 0.0, options_.max_speed_mps);
}

}  // namespace luxloc
