#include "core/imu/still_detector.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace luxloc {

StillDetector::StillDetector(const StillOptions& options) : options_(options) {}

void StillDetector::reset() {
  window_.clear();
  recompute_sums();
  still_ = false;
  force_steady_ = false;
  still_since_ = t_last_ = 0;
  run_sum_g_.setZero();
  run_n_ = 0;
  mag_buckets_.clear();
  mag_sum_.setZero();
  mag_acc_sum_.setZero();
  mag_n_ = 0;
  turning_ = false;
  run_first_bucket_.reset();
  run_last_bucket_.reset();
}

void StillDetector::add_mag(const ImuSample& s) {
  if (!options_.check_mag_turn || !s.has_mag || !s.mag_inB.allFinite() || s.mag_inB.squaredNorm() < 1e-6) return;
  if (mag_n_ == 0) mag_bucket_start_ = s.t;
  mag_sum_ += s.mag_inB;
  mag_acc_sum_ += s.acc_inB;
  ++mag_n_;
  if (s.t - mag_bucket_start_ < seconds_to_ns(options_.mag_bucket_s)) return;
  // The field's horizontal part (perpendicular to the mean specific force, "up" at rest):
  // its direction turns by the full heading change, where the whole field's turns only by
  // the horizontal share (about half at mid-latitudes).
  const Eigen::Vector3d up = mag_acc_sum_.normalized();
  const Eigen::Vector3d m = mag_sum_ / static_cast<double>(mag_n_);
  const Eigen::Vector3d h = m - m.dot(up) * up;
  mag_sum_.setZero();
  mag_acc_sum_.setZero();
  mag_n_ = 0;
  if (!(h.norm() > 0.1 * m.norm())) return;  // near a magnetic pole: no heading in the field
  mag_buckets_.push_back({mag_bucket_start_ + (s.t - mag_bucket_start_) / 2, h.normalized(), up, m.norm(),
                          -std::asin(std::clamp(m.normalized().dot(up), -1.0, 1.0))});
  if (still_) {  // a mean inside the current still run (decided by the samples before this one)
    if (!run_first_bucket_) run_first_bucket_ = mag_buckets_.back();
    run_last_bucket_ = mag_buckets_.back();
  }
  const TimeNs span_ns = seconds_to_ns(options_.mag_turn_span_s);
  while (mag_buckets_.size() > 2 && mag_buckets_.back().t - mag_buckets_[1].t >= span_ns) mag_buckets_.pop_front();
  // Against every older mean, not only the oldest: a device swinging back and forth
  // comes back to where it was.
  turning_ = false;
  const MagBucket& b = mag_buckets_.back();
  for (std::size_t i = 0; i + 1 < mag_buckets_.size() && !turning_; ++i) {
    const MagBucket& a = mag_buckets_[i];
    const double angle = std::atan2(a.dir.cross(b.dir).norm(), a.dir.dot(b.dir));
    turning_ = angle > options_.mag_turn_max_rps * ns_to_seconds(b.t - a.t) + options_.mag_turn_noise_rad;
  }
}

void StillDetector::recompute_sums() {
  // Running sums drift after many add/subtract pairs; rebuilding them now and then keeps
  // the variances exact to rounding.
  sum_g_.setZero();
  sum_gg_.setZero();
  sum_a_.setZero();
  sum_aa_.setZero();
  for (const Entry& e : window_) {
    sum_g_ += e.gyro;
    sum_gg_ += e.gyro.cwiseAbs2();
    sum_a_ += e.acc;
    sum_aa_ += e.acc.cwiseAbs2();
  }
  pops_since_recompute_ = 0;
}

bool StillDetector::update(const ImuSample& s) {
  if (!s.gyro_inB.allFinite() || !s.acc_inB.allFinite()) return still_;
  if (!window_.empty() && s.t <= window_.back().t) {
    // Time went backwards: start over rather than mix two timelines.
    reset();
  }
  add_mag(s);
  window_.push_back({s.t, s.gyro_inB, s.acc_inB});
  sum_g_ += s.gyro_inB;
  sum_gg_ += s.gyro_inB.cwiseAbs2();
  sum_a_ += s.acc_inB;
  sum_aa_ += s.acc_inB.cwiseAbs2();
  const TimeNs window_ns = seconds_to_ns(options_.window_s);
  bool full = false;
  while (window_.size() > 1 && s.t - window_[1].t >= window_ns) {
    const Entry& e = window_.front();
    sum_g_ -= e.gyro;
    sum_gg_ -= e.gyro.cwiseAbs2();
    sum_a_ -= e.acc;
    sum_aa_ -= e.acc.cwiseAbs2();
    window_.pop_front();
    full = true;
    if (++pops_since_recompute_ > 4096) recompute_sums();
  }
  full = full || (s.t - window_.front().t >= window_ns);
  force_steady_ = full && force_quiet();
  const bool quiet = full && evaluate();  // gyro and accelerometer at rest
  const bool now_still = quiet && !turning_;
  // The run was a slow turn only when it ends on the field's verdict alone. A run that ends
  // because the device starts to move was rest: the start of a walk turns the field in the
  // body too, and taking that for a slow turn threw away the bias learnt at rest (issue 11:
  // the poor grade's 1 deg/s bias learnt in the first 2 s, forgotten at the first step).
  if (still_ && !now_still) last_run_was_turn_ = quiet && turning_;
  if (!quiet) {
    // Moving: the field turns in the body, and means from the walk compared with the first
    // means of a stop read as a turn for the next 2 s, so a 2 s stop never counted as rest
    // (the walk's stops learnt no bias). The turn test compares means of the quiet time only.
    mag_buckets_.clear();
    mag_sum_.setZero();
    mag_acc_sum_.setZero();
    mag_n_ = 0;
    turning_ = false;
  }
  if (now_still && !still_) {
    still_since_ = s.t;
    run_t0_ = window_.front().t;
    run_first_bucket_.reset();
    run_last_bucket_.reset();
    run_sum_g_ = sum_g_;
    run_n_ = window_.size();
  } else if (now_still) {
    run_sum_g_ += s.gyro_inB;
    ++run_n_;
  }
  if (now_still) run_t1_ = s.t;
  still_ = now_still;
  t_last_ = s.t;
  return still_;
}

bool StillDetector::evaluate() const { return gyro_quiet() && force_quiet(); }

bool StillDetector::gyro_quiet() const {
  const double n = static_cast<double>(window_.size());
  if (n < 3) return false;
  const Eigen::Vector3d mg = sum_g_ / n;
  const Eigen::Vector3d var_g = (sum_gg_ / n - mg.cwiseAbs2()).cwiseMax(0.0);
  const double sg = options_.gyro_std_max_rps;
  return var_g.maxCoeff() <= sg * sg && mg.norm() <= options_.gyro_mean_max_rps;
}

bool StillDetector::force_quiet() const {
  const double n = static_cast<double>(window_.size());
  if (n < 3) return false;
  const Eigen::Vector3d ma = sum_a_ / n;
  const Eigen::Vector3d var_a = (sum_aa_ / n - ma.cwiseAbs2()).cwiseMax(0.0);
  const double sa = options_.acc_std_max_mps2;
  return var_a.maxCoeff() <= sa * sa && std::abs(ma.norm() - options_.gravity) <= options_.acc_norm_tolerance_mps2;
}

std::optional<double> StillDetector::run_field_turn_rate_rps() const {
  if (!run_first_bucket_ || !run_last_bucket_ ||
      ns_to_seconds(run_last_bucket_->t - run_first_bucket_->t) < options_.mag_rate_min_span_s || run_t1_ <= run_t0_)
    return std::nullopt;
  if (std::abs(run_last_bucket_->norm / run_first_bucket_->norm - 1.0) > options_.mag_rate_max_norm_change ||
      std::abs(run_last_bucket_->dip - run_first_bucket_->dip) > options_.mag_rate_max_dip_change_rad)
    return std::nullopt;
  // The body turns one way, the field seen in it the other: minus the field's signed turn.
  const Eigen::Vector3d& a = run_first_bucket_->dir;
  const Eigen::Vector3d& b = run_last_bucket_->dir;
  const double field_turn = std::atan2(a.cross(b).dot(run_last_bucket_->up), a.dot(b));
  return -field_turn / ns_to_seconds(run_t1_ - run_t0_);
}

double StillDetector::still_duration_s() const { return still_ ? ns_to_seconds(t_last_ - still_since_) : 0.0; }

Eigen::Vector3d StillDetector::mean_gyro() const {
  return window_.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(sum_g_ / static_cast<double>(window_.size()));
}
Eigen::Vector3d StillDetector::still_mean_gyro() const {
  return run_n_ == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(run_sum_g_ / static_cast<double>(run_n_));
}
Eigen::Vector3d StillDetector::mean_acc() const {
  return window_.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(sum_a_ / static_cast<double>(window_.size()));
}

}  // namespace luxloc
