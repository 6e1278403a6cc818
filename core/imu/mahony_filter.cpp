#include "core/imu/mahony_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace luxloc {

namespace {
StillOptions attitude_still_options(const MahonyOptions& o) {
  StillOptions s = o.still;
  s.check_mag_turn = o.still_checks_mag_turn;
  return s;
}
}  // namespace

MahonyFilter::MahonyFilter(const MahonyOptions& options) : options_(options), still_(attitude_still_options(options)) {}

void MahonyFilter::set_mag_reference(const Eigen::Vector3d& mag_inB, const Eigen::Vector3d& up_inB) {
  mag_ref_norm_ = mag_inB.norm();
  mag_ref_dip_ = -std::asin(std::clamp(mag_inB.normalized().dot(up_inB), -1.0, 1.0));
  mag_ref_valid_ = true;
  mag_disturbed_s_ = -1.0;
}

void MahonyFilter::align(const Eigen::Vector3d& acc_inB, const Eigen::Vector3d* mag_inB) {
  // Accelerometer at rest reads +g along world up: roll and pitch follow (ZYX Euler).
  const Eigen::Vector3d a = acc_inB.normalized();
  const double roll = std::atan2(a.y(), a.z());
  const double pitch = std::atan2(-a.x(), std::sqrt(a.y() * a.y() + a.z() * a.z()));
  double yaw = 0.0;
  const Eigen::Matrix3d R_tilt =
      (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  if (mag_inB && options_.use_magnetometer && mag_inB->allFinite() && mag_inB->norm() > 1e-6) {
    // Tilt-compensate: the field in a level frame whose x is body-forward's horizontal part.
    const Eigen::Vector3d m = R_tilt * *mag_inB;
    // The horizontal field points north (+y in ENU): the body heading is yaw with
    // north = R_z(yaw) * m_level  =>  yaw = atan2(m_x, m_y) for m expressed in level body axes.
    yaw = std::atan2(m.x(), m.y());
    set_mag_reference(*mag_inB, a);
  }
  q_ = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::Quaterniond(R_tilt));
  q_.normalize();
  initialized_ = true;
}

Eigen::Vector3d MahonyFilter::magnetometer_error(const Eigen::Matrix3d& R, const ImuSample& s, double dt,
                                                 bool converging) {
  if (!s.has_mag || !options_.use_magnetometer || s.mag_inB.norm() < 1e-6) return Eigen::Vector3d::Zero();
  if (mag_held_ && !converging) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d m = s.mag_inB.normalized();
  const Eigen::Vector3d up_inB = R.transpose().col(2);
  if (!mag_ref_valid_) set_mag_reference(s.mag_inB, up_inB);  // aligned without a magnetometer
  // Reference field: the measured field rotated to the world, its horizontal part put on
  // north (+y, ENU), so the magnetometer only corrects heading (Mahony 2008, eq. 34). The
  // error is taken between the horizontal directions only: m x b of the unit vectors would
  // scale it by cos^2(dip) (~0.2 at mid latitudes), slowing the heading correction 5-fold.
  const Eigen::Vector3d h = R * m;
  const double h_horizontal = std::hypot(h.x(), h.y());
  const double dip = -std::asin(std::clamp(m.dot(up_inB), -1.0, 1.0));
  // Heading innovation: how far the field's horizontal direction is from north.
  const double innovation = h_horizontal < 0.1 ? 0.0 : std::atan2(h.x(), h.y());
  const bool bad_magnitude = std::abs(s.mag_inB.norm() - mag_ref_norm_) > options_.mag_rejection * mag_ref_norm_;
  const bool bad_dip = std::abs(dip - mag_ref_dip_) > options_.mag_dip_rejection_rad;
  // The heading gate needs a converged heading; after adopting a new field it waits until
  // the heading agrees with it again.
  if (mag_recovering_ && std::abs(innovation) < 0.5 * options_.mag_heading_gate_rad) mag_recovering_ = false;
  const bool bad_heading = !converging && !mag_recovering_ && std::abs(innovation) > mag_heading_gate_now();
  if (bad_magnitude || bad_dip || bad_heading) {
    if (mag_disturbed_s_ < 0.0) mag_disturbed_s_ = 0.0;
    // The clock runs only while moving: a still device has not walked into another field.
    if (!still_.still()) mag_disturbed_s_ += dt;
    if (mag_disturbed_s_ < options_.mag_rejection_timeout_s) {
      ++rejections_.mag_samples;
      rejections_.mag_s += dt;
      if (bad_magnitude) ++rejections_.mag_magnitude;
      if (bad_dip) ++rejections_.mag_dip;
      if (bad_heading) ++rejections_.mag_heading;
      last_mag_rejected_ = true;
      return Eigen::Vector3d::Zero();
    }
    set_mag_reference(s.mag_inB, up_inB);  // a lasting change: the new normal
    ++rejections_.mag_adopted;
    mag_recovering_ = true;
  } else {
    mag_disturbed_s_ = -1.0;
  }
  // The field corrects the heading with time constant 1 / kp_heading: so shrinks the bound.
  heading_drift_rad_ *= std::max(0.0, 1.0 - options_.kp_heading * dt);
  t_mag_used_ = s.t;
  mag_used_ = true;
  if (h_horizontal < 0.1) return Eigen::Vector3d::Zero();  // field nearly vertical: no heading
  // (h_xy / |h_xy|) x north, about world up: the sine of the heading error; applied about
  // the body's up axis.
  return up_inB * (h.x() / h_horizontal);
}

void MahonyFilter::update(const ImuSample& s) {
  if (!s.acc_inB.allFinite() || !s.gyro_inB.allFinite() || (s.has_mag && !s.mag_inB.allFinite())) {
    ++rejected_;  // NaN must never reach the attitude
    return;
  }
  if (!initialized_) {
    still_.update(s);
    align(s.acc_inB, s.has_mag ? &s.mag_inB : nullptr);
    t_ = t_start_ = s.t;
    return;
  }
  double dt = ns_to_seconds(s.t - t_);
  if (dt <= 0.0) {
    ++rejected_;
    return;
  }
  const bool was_still = still_.still();
  still_.update(s);
  // A still run that turned out to be a slow turn (the field turned in the body): its mean
  // rate was bias plus turn. Back to the bias before the run when a rest has taught one.
  // Before any (the first standstill, ended by a walk that starts on a curve), that would
  // be no bias at all: the run's mean less the turn the field measured over it is then the
  // best estimate (issue 11: the poor grade's 1 deg/s learnt in the first 2 s was dropped).
  if (options_.bias_at_rest && was_still && !still_.still()) {
    if (!still_.last_run_was_turn()) {
      bias_from_rest_ = true;
    } else if (const std::optional<double> rate = still_.run_field_turn_rate_rps(); rate && !bias_from_rest_) {
      bias_ = still_.still_mean_gyro() - q_.toRotationMatrix().transpose().col(2) * *rate;
    } else {
      bias_ = bias_before_still_;
    }
  }
  if (!was_still && still_.still()) bias_before_still_ = bias_;
  dt = std::min(dt, options_.max_dt_s);
  t_ = s.t;

  const Eigen::Matrix3d R = q_.toRotationMatrix();
  const bool converging = ns_to_seconds(s.t - t_start_) < options_.init_duration_s;
  Eigen::Vector3d e_acc = Eigen::Vector3d::Zero();
  const double a_norm = s.acc_inB.norm();
  last_acc_rejected_ = !(a_norm > 1e-6 && std::abs(a_norm - options_.gravity) < options_.acc_rejection * options_.gravity);
  if (!last_acc_rejected_) {
    const Eigen::Vector3d v_up_inB = R.transpose().col(2);  // predicted "up" in body
    e_acc = (s.acc_inB / a_norm).cross(v_up_inB);
  } else {
    ++rejections_.acc_samples;
    rejections_.acc_s += dt;
  }
  last_mag_rejected_ = false;
  // The gyro's possible heading error grows while it integrates (the gate's widening).
  const double yaw_rate = std::abs(R.row(2).dot(s.gyro_inB - bias_));
  heading_drift_rad_ += (options_.gyro_bias_uncertainty_rps + options_.gyro_scale_uncertainty * yaw_rate) * dt;
  const Eigen::Vector3d e_mag = magnetometer_error(R, s, dt, converging);
  const double kp = converging ? options_.kp_init : options_.kp;
  const double kp_heading = converging ? options_.kp_init : options_.kp_heading;
  if (still_.still() && options_.bias_at_rest) {
    // At rest the mean rate is the bias (Earth's rate, < 0.005 deg/s, is below the noise).
    bias_ = still_.still_mean_gyro();
  } else if (!converging) {
    // Integral terms (- bias estimate), each loop with its own gain: the magnetometer's
    // error lies along the body's up axis, so it learns the bias about the vertical.
    // After adopting a new field the heading error is an offset, not a bias: not integrated.
    bias_ -= (options_.ki * e_acc + (mag_recovering_ ? 0.0 : options_.ki_heading) * e_mag) * dt;
  }
  const Eigen::Vector3d w = s.gyro_inB - bias_ + kp * e_acc + kp_heading * e_mag;
  last_gyro_corrected_ = s.gyro_inB - bias_;

  // q <- q * exp(w dt / 2)
  const double angle = w.norm() * dt;
  if (angle > 1e-12) q_ = q_ * Eigen::Quaterniond(Eigen::AngleAxisd(angle, w.normalized()));
  q_.normalize();
}

void MahonyFilter::correct_heading(double dyaw_rad, double drate_rps) {
  if (!initialized_ || !std::isfinite(dyaw_rad) || !std::isfinite(drate_rps)) return;
  // A turn about the world vertical, applied on the world side: R' = Rz(dyaw) R.
  q_ = Eigen::Quaterniond(Eigen::AngleAxisd(dyaw_rad, Eigen::Vector3d::UnitZ())) * q_;
  q_.normalize();
  // The integrated rate is gyro - bias; to add drate about the world vertical, take it off
  // the bias along the vertical seen in the body.
  bias_ -= q_.toRotationMatrix().transpose().col(2) * drate_rps;
  // The heading was just fixed from outside: the gyro's drift since starts from here.
  heading_drift_rad_ = 0.0;
}

double MahonyFilter::since_mag_correction_s() const {
  return mag_used_ ? ns_to_seconds(t_ - t_mag_used_) : std::numeric_limits<double>::infinity();
}

double MahonyFilter::yaw() const {
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}
double MahonyFilter::roll() const {
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  return std::atan2(R(2, 1), R(2, 2));
}
double MahonyFilter::pitch() const {
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  return std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
}

}  // namespace luxloc
