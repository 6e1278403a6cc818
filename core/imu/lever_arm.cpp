#include "core/imu/lever_arm.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace luxloc {
namespace {

Eigen::Matrix2d rotation(double a) { return Eigen::Rotation2Dd(a).toRotationMatrix(); }

}  // namespace

LeverArm::LeverArm(const LeverArmOptions& options) : options_(options) {}

Eigen::Vector2d LeverArm::offset_inW(double yaw_rad) const {
  return lever_ ? Eigen::Vector2d(rotation(yaw_rad) * *lever_) : Eigen::Vector2d::Zero();
}

void LeverArm::update_standing(TimeNs t, double yaw_rad, double yaw_rate_rps, const Eigen::Vector2d& a_inW) {
  if (!std::isfinite(yaw_rad) || !std::isfinite(yaw_rate_rps) || !a_inW.allFinite()) return;
  if (!have_t_) {
    have_t_ = true;
    t_last_ = t;
    rate_ = yaw_rate_rps;
    return;
  }
  const double dt = std::clamp(ns_to_seconds(t - t_last_), 0.0, 0.1);
  t_last_ = t;
  if (dt <= 0.0) return;
  const double before = rate_;
  rate_ += (yaw_rate_rps - rate_) * std::min(1.0, dt / options_.rate_tau_s);
  const double rate_dot = (rate_ - before) / dt;
  if (std::abs(rate_) < options_.min_rate_rps) {
    if (turning_) finish_turn();
    return;
  }
  turning_ = true;
  // p'' = M l with M = (psi'' J - psi'^2 I) R(psi); M^T M = (psi''^2 + psi'^4) I.
  Eigen::Matrix2d K;
  K << -rate_ * rate_, -rate_dot, rate_dot, -rate_ * rate_;
  const Eigen::Matrix2d M = K * rotation(yaw_rad);
  turn_n_ += (rate_dot * rate_dot + rate_ * rate_ * rate_ * rate_) * dt;
  turn_b_ += M.transpose() * a_inW * dt;
  turn_e_ += a_inW.squaredNorm() * dt;
}

void LeverArm::interrupt() {
  if (turning_) finish_turn();
  have_t_ = false;
}

void LeverArm::finish_turn() {
  turning_ = false;
  const double n = turn_n_, e = turn_e_;
  const Eigen::Vector2d b = turn_b_;
  turn_n_ = turn_e_ = 0.0;
  turn_b_.setZero();
  if (!(n >= options_.min_excitation)) return;  // too little turn to say anything
  const Eigen::Vector2d l = b / n;
  // Residual of the fit: e - 2 l.b + n |l|^2 = e - |b|^2 / n.
  const double fit = e > 0.0 ? 1.0 - (e - b.squaredNorm() / n) / e : 0.0;
  if (!(fit >= options_.min_fit) || !(l.norm() <= options_.max_length_m)) {
    ++turns_refused_;
    return;
  }
  all_n_ += n;
  all_b_ += b;
  lever_ = all_b_ / all_n_;
  ++turns_used_;
}

}  // namespace luxloc
