#include "core/imu/planar_inertial.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace luxloc {

PlanarInertialIntegrator::PlanarInertialIntegrator(const PlanarInertialOptions& options)
    : options_(options), still_(options.still) {}

void PlanarInertialIntegrator::update(const ImuSample& s, const Eigen::Matrix3d& R_BtoW) {
  if (!s.acc_inB.allFinite() || !s.gyro_inB.allFinite() || !R_BtoW.allFinite()) return;
  if (t_last_ && s.t <= *t_last_) return;
  still_.update(s);
  const Eigen::Vector3d f_inW = R_BtoW * s.acc_inB;
  const Eigen::Vector2d a_inW = f_inW.head<2>();  // gravity is vertical: the horizontal part is motion
  const double yaw = std::atan2(R_BtoW(1, 0), R_BtoW(0, 0));
  if (!started_) {
    acc_.t0 = acc_.t1 = s.t;
    started_ = true;
  }
  if (t_last_) {
    const double dt = std::min(ns_to_seconds(s.t - *t_last_), options_.max_dt_s);
    // Trapezoidal in acceleration: the velocity change over the interval is exact for a
    // linearly varying acceleration, the displacement second-order accurate.
    const Eigen::Vector2d dv = 0.5 * (a_last_ + a_inW) * dt;
    acc_.dp_inW += (v_inW_ + 0.5 * dv) * dt;
    v_inW_ += dv;
    acc_.dyaw_rad += std::remainder(yaw - *yaw_last_, 2.0 * std::numbers::pi);
  }
  if (options_.zero_velocity_at_rest && still_.still()) v_inW_.setZero();
  a_last_ = a_inW;
  t_last_ = s.t;
  yaw_last_ = yaw;
  acc_.t1 = s.t;
  acc_.v_inW = v_inW_;
  acc_.at_rest = still_.still();
}

PlanarIncrement PlanarInertialIntegrator::take() {
  PlanarIncrement out = acc_;
  acc_ = PlanarIncrement{};
  acc_.t0 = acc_.t1 = out.t1;
  acc_.v_inW = v_inW_;
  acc_.at_rest = out.at_rest;
  return out;
}

}  // namespace luxloc
