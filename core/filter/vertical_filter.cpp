#include "core/filter/vertical_filter.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

VerticalFilter::VerticalFilter(const VerticalFilterOptions& options, double nominal_height_m) : options_(options) {
  x_ << nominal_height_m, 0.0;
  P_.setZero();
  P_(0, 0) = options.height_sigma0_m * options.height_sigma0_m;
  P_(1, 1) = options.speed_sigma0_mps * options.speed_sigma0_mps;
}

void VerticalFilter::predict(TimeNs t) {
  if (!t_) {
    t_ = t;
    return;
  }
  if (t <= *t_) return;
  const double dt = ns_to_seconds(t - *t_);
  t_ = t;
  // The discrete Wiener process model (constant velocity, white acceleration).
  Eigen::Matrix2d F;
  F << 1.0, dt, 0.0, 1.0;
  Eigen::Matrix2d Q;
  const double q = options_.accel_psd;
  Q << q * dt * dt * dt / 3.0, q * dt * dt / 2.0, q * dt * dt / 2.0, q * dt;
  x_ = F * x_;
  P_ = F * P_ * F.transpose() + Q;
  if (x_(0) < options_.min_height_m || x_(0) > options_.max_height_m) {
    x_(0) = std::clamp(x_(0), options_.min_height_m, options_.max_height_m);
    x_(1) = 0.0;
  }
}

VerticalFilter::Outcome VerticalFilter::update(TimeNs t, double z_m, double sigma_m) {
  if (!std::isfinite(z_m) || !(sigma_m > 0.0) || !std::isfinite(sigma_m)) return Outcome::skipped;
  predict(t);
  const double R = sigma_m * sigma_m;
  double S = P_(0, 0) + R;
  const double nu = z_m - x_(0);
  if (std::abs(nu) > options_.gate_sigma * std::sqrt(S)) {
    if (++gated_run_ < options_.reopen_after_gated) {
      ++stats_.gated;
      return Outcome::gated;
    }
    // VerticalFilterOptions::reopen_after_gated: the state is wrong; reopen it.
    P_(0, 0) = std::max(P_(0, 0), options_.height_sigma0_m * options_.height_sigma0_m);
    P_(1, 1) = std::max(P_(1, 1), options_.speed_sigma0_mps * options_.speed_sigma0_mps);
    S = P_(0, 0) + R;
    ++stats_.reopened;
  }
  gated_run_ = 0;
  // Kalman update with H = [1 0], Joseph form.
  const Eigen::Vector2d K = P_.col(0) / S;
  x_ += K * nu;
  Eigen::Matrix2d I_KH = Eigen::Matrix2d::Identity();
  I_KH.col(0) -= K;
  P_ = I_KH * P_ * I_KH.transpose() + R * K * K.transpose();
  ++stats_.used;
  return Outcome::used;
}

}  // namespace luxloc
