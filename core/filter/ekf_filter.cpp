#include "core/filter/ekf_filter.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace luxloc {

void EkfFilter::initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) {
  if (!p.allFinite()) return;
  x_ << p, 0.0, 0.0, options_.gait.scale0, 0.0;
  P_.setZero();
  P_.topLeftCorner<2, 2>() =
      cov_p.allFinite() ? Eigen::Matrix2d(0.5 * (cov_p + cov_p.transpose())) : Eigen::Matrix2d::Identity();
  P_.block<2, 2>(2, 2) = Eigen::Matrix2d::Identity() * options_.init_speed_sigma * options_.init_speed_sigma;
  P_(4, 4) = options_.gait.scale_sigma0 * options_.gait.scale_sigma0;
  P_(5, 5) = options_.gait.heading_offset_sigma0 * options_.gait.heading_offset_sigma0;
  condition();
  consecutive_rejections_ = 0;
  initialized_ = true;
}

void EkfFilter::predict_gait(const MotionInput& u) {
  const GaitInput& g = u.gait;
  const double dt = u.dt;
  const double vmax = options_.max_speed > 0 ? options_.max_speed : std::numeric_limits<double>::infinity();
  const double s = std::clamp(g.speed_mps, 0.0, vmax);
  const double k = x_(4), d = x_(5);
  const double a = g.heading_rad + d;
  const Eigen::Vector2d u_a(std::cos(a), std::sin(a)), u_perp(-std::sin(a), std::cos(a));
  const Eigen::Vector2d v_new = k * s * u_a;
  // Jacobian: v' depends on k and d only; p' = p + dt (v + v') / 2.
  Matrix6 F = Matrix6::Identity();
  F.block<2, 2>(2, 2).setZero();
  F.block<2, 1>(2, 4) = s * u_a;
  F.block<2, 1>(2, 5) = k * s * u_perp;
  F.block<2, 2>(0, 2) = 0.5 * dt * Eigen::Matrix2d::Identity();
  F.block<2, 2>(0, 4) = 0.5 * dt * F.block<2, 2>(2, 4);
  // Process noise: the per-step length / heading noise as along / across-track diffusion
  // (as the particle filter), the calibration states' random walks.
  const double T = g.step_period_s > 0.05 ? g.step_period_s : 0.55;
  const double l = s * T, q0 = std::max(0.0, options_.gait.position_psd);
  const Eigen::Vector2d u_h(std::cos(g.heading_rad), std::sin(g.heading_rad)), u_hp(-u_h.y(), u_h.x());
  const double turn = std::isfinite(g.turn_rate_rps) ? options_.gait.turn_noise * std::abs(g.turn_rate_rps) * T * l : 0.0;
  const double q_turn = turn * turn / T;
  const double q_along = (g.length_sigma_m * g.length_sigma_m / T + q0 + q_turn) * dt;
  const double q_cross = (l * l * g.heading_sigma_rad * g.heading_sigma_rad / T + q0 + q_turn) * dt;
  Matrix6 Q = Matrix6::Zero();
  Q.topLeftCorner<2, 2>() = q_along * u_h * u_h.transpose() + q_cross * u_hp * u_hp.transpose();
  Q(4, 4) = options_.gait.scale_walk * options_.gait.scale_walk * dt;
  Q(5, 5) = options_.gait.heading_offset_walk * options_.gait.heading_offset_walk * dt;
  Vector6 x = x_;
  x.head<2>() += 0.5 * dt * (x_.segment<2>(2) + v_new);
  x.segment<2>(2) = v_new;
  const Matrix6 P = F * P_ * F.transpose() + Q;
  if (!x.allFinite() || !P.allFinite()) return;
  x_ = x;
  x_(4) = std::clamp(x_(4), options_.gait.min_scale, options_.gait.max_scale);
  P_ = P;
  condition();
}

void EkfFilter::predict(const MotionInput& u) {
  if (!initialized_ || !(u.dt > 0.0) || !std::isfinite(u.dt)) return;
  if (u.shift_inW.allFinite()) x_.head<2>() += u.shift_inW;
  if (u.has_gait) {
    const GaitInput& g = u.gait;
    if (std::isfinite(g.speed_mps) && std::isfinite(g.heading_rad) && std::isfinite(g.length_sigma_m) &&
        std::isfinite(g.heading_sigma_rad) && std::isfinite(g.step_period_s))
      predict_gait(u);
    return;
  }
  const double dt = u.dt;
  const Eigen::Vector2d a = (u.has_acc && u.acc_inW.allFinite()) ? u.acc_inW : Eigen::Vector2d::Zero();
  const double d = options_.velocity_tau_s > 0 ? std::exp(-dt / options_.velocity_tau_s) : 1.0;
  const double q = std::max(0.0, options_.accel_noise_psd);
  // Per axis: F = [[1, dt (1 + d) / 2], [0, d]], control B a = [dt^2 d / 2, dt d] a,
  // noise G w with G = [dt / 2, 1], var(w) = q dt.
  Matrix6 F = Matrix6::Identity();  // k, d: identity (inert)
  F(0, 2) = F(1, 3) = 0.5 * dt * (1.0 + d);
  F(2, 2) = F(3, 3) = d;
  Vector6 Bu = Vector6::Zero();
  Bu(0) = 0.5 * dt * dt * d * a.x();
  Bu(1) = 0.5 * dt * dt * d * a.y();
  Bu(2) = dt * d * a.x();
  Bu(3) = dt * d * a.y();
  Matrix6 Q = Matrix6::Zero();
  const double qv = q * dt;
  for (int i = 0; i < 2; ++i) {
    Q(i, i) = qv * 0.25 * dt * dt;
    Q(i, i + 2) = Q(i + 2, i) = qv * 0.5 * dt;
    Q(i + 2, i + 2) = qv;
  }
  const Vector6 x = F * x_ + Bu;
  const Matrix6 P = F * P_ * F.transpose() + Q;
  if (!x.allFinite() || !P.allFinite()) return;  // NaN guard: keep the last good state
  x_ = x;
  P_ = P;
  // A walking device: clamp the speed (the particle filter clamps each particle).
  const double speed = x_.segment<2>(2).norm();
  if (options_.max_speed > 0 && speed > options_.max_speed) x_.segment<2>(2) *= options_.max_speed / speed;
  condition();
}

CorrectionResult EkfFilter::update(int row, const Eigen::Vector2d& z, const Eigen::Matrix2d& R, double gate) {
  CorrectionResult r;
  Eigen::Matrix<double, 2, 6> H = Eigen::Matrix<double, 2, 6>::Zero();
  H(0, row) = H(1, row + 1) = 1.0;
  const Eigen::Vector2d innov = z - H * x_;
  const Eigen::Matrix2d S = H * P_ * H.transpose() + R;
  const Eigen::LDLT<Eigen::Matrix2d> ldlt(S);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return r;
  r.mahalanobis = std::sqrt(innov.dot(ldlt.solve(innov)));
  if (!(r.mahalanobis <= gate)) return r;
  // K = P H^T S^-1; Joseph form P = (I - K H) P (I - K H)^T + K R K^T stays symmetric
  // positive semi-definite under rounding, unlike (I - K H) P.
  const Eigen::Matrix<double, 6, 2> K = ldlt.solve(H * P_).transpose();
  const Matrix6 IKH = Matrix6::Identity() - K * H;
  Vector6 x = x_ + K * innov;
  x(4) = std::clamp(x(4), options_.gait.min_scale, options_.gait.max_scale);
  const Matrix6 P = IKH * P_ * IKH.transpose() + K * R * K.transpose();
  if (!x.allFinite() || !P.allFinite()) {
    r.mahalanobis = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  x_ = x;
  P_ = P;
  condition();
  r.accepted = true;
  return r;
}

CorrectionResult EkfFilter::correct(const PositionMeasurement& m) {
  CorrectionResult r;
  if (!usable(m)) {
    ++rejected_;
    return r;
  }
  if (!initialized_) {
    initialize(m.z, m.R * 4.0);
    r.accepted = r.reinitialized = true;
    return r;
  }
  r = update(0, m.z, m.R, m.gate_sigma);
  if (r.accepted) {
    consecutive_rejections_ = 0;
    return r;
  }
  ++rejected_;
  if (++consecutive_rejections_ >= options_.max_consecutive_rejections) {
    // Lost track (kidnapped, or the prediction drifted during a dropout): restart at the
    // fix, keeping nothing of the old velocity.
    initialize(m.z, m.R * 4.0);
    ++reinits_;
    r.accepted = r.reinitialized = true;
  }
  return r;
}

CorrectionResult EkfFilter::correct_velocity(const VelocityMeasurement& m) {
  if (!initialized_ || !usable(m)) {
    ++rejected_;
    return {};
  }
  CorrectionResult r = update(2, m.v, m.R, m.gate_sigma);
  if (!r.accepted) ++rejected_;
  return r;
}

void EkfFilter::condition() {
  P_ = 0.5 * (P_ + P_.transpose());
  for (int i = 0; i < 6; ++i) {
    // k and d: capped at their prior spread (they cannot grow less certain than that).
    const double cap = i < 2   ? options_.max_position_variance
                       : i < 4 ? options_.max_velocity_variance
                       : i == 4 ? options_.gait.scale_sigma0 * options_.gait.scale_sigma0
                                : options_.gait.heading_offset_sigma0 * options_.gait.heading_offset_sigma0;
    const double v = std::clamp(P_(i, i), 1e-12, std::max(cap, 1e-12));
    if (v != P_(i, i)) {
      // Rescale row/column i so correlations (and positive definiteness) survive.
      const double s = P_(i, i) > 0.0 ? std::sqrt(v / P_(i, i)) : 0.0;
      P_.row(i) *= s;
      P_.col(i) *= s;
      P_(i, i) = v;
    }
  }
}

PlanarEstimate EkfFilter::estimate() const {
  PlanarEstimate e;
  if (!initialized_) return e;
  e.p = x_.head<2>();
  e.v = x_.segment<2>(2);
  e.cov_p = P_.topLeftCorner<2, 2>();
  e.valid = x_.allFinite() && P_.allFinite();
  return e;
}

}  // namespace luxloc
