#include "core/imu/still_detector.hpp"

#include <cmath>

namespace luxloc {

StillDetector::StillDetector(const StillOptions& options) : options_(options) {}

void StillDetector::reset() {
  window_.clear();
  recompute_sums();
  still_ = false;
  still_since_ = t_last_ = 0;
  run_sum_g_.setZero();
  run_n_ = 0;
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
  const bool now_still = full && evaluate();
  if (now_still && !still_) {
    still_since_ = s.t;
    run_sum_g_ = sum_g_;
    run_n_ = window_.size();
  } else if (now_still) {
    run_sum_g_ += s.gyro_inB;
    ++run_n_;
  }
  still_ = now_still;
  t_last_ = s.t;
  return still_;
}

bool StillDetector::evaluate() const {
  const double n = static_cast<double>(window_.size());
  if (n < 3) return false;
  const Eigen::Vector3d mg = sum_g_ / n, ma = sum_a_ / n;
  const Eigen::Vector3d var_g = (sum_gg_ / n - mg.cwiseAbs2()).cwiseMax(0.0);
  const Eigen::Vector3d var_a = (sum_aa_ / n - ma.cwiseAbs2()).cwiseMax(0.0);
  const double sg = options_.gyro_std_max_rps, sa = options_.acc_std_max_mps2;
  return var_g.maxCoeff() <= sg * sg && var_a.maxCoeff() <= sa * sa && mg.norm() <= options_.gyro_mean_max_rps &&
         std::abs(ma.norm() - options_.gravity) <= options_.acc_norm_tolerance_mps2;
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
