#include "core/imu/pdr.hpp"

#include <cmath>
#include <numbers>

namespace luxloc {

PedestrianDeadReckoning::PedestrianDeadReckoning(const PdrOptions& options)
    : options_(options), impacts_(options.impacts), detector_(options.detector), length_(options.length), gravity_(options.gravity_window) {}

void PedestrianDeadReckoning::update(const ImuSample& s, const Eigen::Matrix3d& R_BtoW) {
  if (!s.acc_inB.allFinite() || !R_BtoW.allFinite()) return;
  if (!yaw_history_.empty() && s.t <= yaw_history_.back().first) return;
  const std::optional<TimeNs> t_prev = yaw_history_.empty() ? std::nullopt : std::optional(yaw_history_.back().first);
  yaw_history_.emplace_back(s.t, std::atan2(R_BtoW(1, 0), R_BtoW(0, 0)));
  // Keep enough yaw history to cover the longest step plus the detection delay.
  const TimeNs keep = seconds_to_ns(options_.detector.max_interval_s + 2.0 * options_.detector.min_interval_s +
                                    options_.detector.smoothing_s);
  while (yaw_history_.size() > 1 && s.t - yaw_history_.front().first > keep) yaw_history_.pop_front();

  // No gyroscope: the attitude filter's vertical goes stale on a device that re-orients
  // while it walks (a bag, a pocket); the accelerometer's mean over a stride does not.
  gravity_.add(s.t, s.acc_inB);
  if (!last_gyro_t_ || !(s.gyro_inB.array() == 0.0).all()) last_gyro_t_ = s.t;
  gyro_absent_ = s.t - *last_gyro_t_ >= seconds_to_ns(options_.gyro_absent_after_s);
  if (gyro_absent_ && t_prev) gyro_absent_ns_ += s.t - *t_prev;
  const double a_up = gyro_absent_ ? s.acc_inB.dot(gravity_.up_inB()) - options_.gravity
                                   : (R_BtoW * s.acc_inB).z() - options_.gravity;
  // Heel-strike impacts out first (ImpactFilter): a clean stream passes sample by sample.
  for (const auto& [t, a] : impacts_.update(s.t, a_up))
    if (const std::optional<DetectedStep> d = detector_.update(t, a)) add_step(*d);
}

void PedestrianDeadReckoning::finish() {
  if (const std::optional<DetectedStep> d = detector_.flush()) add_step(*d);
}

void PedestrianDeadReckoning::add_step(const DetectedStep& d) {
  Step step;
  step.t = d.t;
  step.interval_s = d.interval_s;
  step.swing_mps2 = d.swing();
  step.length_m = length_.length_m(d);
  step.length_sigma_m = length_.sigma_m(step.length_m);
  // The step spans from the previous heel strike (or one nominal step before, after a stop).
  const TimeNs span = d.interval_s > 0.0 ? seconds_to_ns(d.interval_s) : seconds_to_ns(0.55);
  step.heading_rad = std::remainder(mean_heading(d.t - span, d.t) + options_.heading_offset_rad, 2.0 * std::numbers::pi);
  step.heading_sigma_rad = options_.heading_sigma_rad;

  p_inW_ += step.length_m * Eigen::Vector2d(std::cos(step.heading_rad), std::sin(step.heading_rad));
  distance_m_ += step.length_m;
  ++count_;
  pending_.push_back(step);
}

double PedestrianDeadReckoning::mean_heading(TimeNs from, TimeNs to) const {
  double c = 0.0, s = 0.0;
  for (const auto& [t, yaw] : yaw_history_) {
    if (t < from || t > to) continue;
    c += std::cos(yaw);
    s += std::sin(yaw);
  }
  if (c == 0.0 && s == 0.0) return yaw_history_.empty() ? 0.0 : yaw_history_.back().second;
  return std::atan2(s, c);
}

std::optional<Step> PedestrianDeadReckoning::pop_step() {
  if (pending_.empty()) return std::nullopt;
  Step s = pending_.front();
  pending_.pop_front();
  return s;
}

}  // namespace luxloc
