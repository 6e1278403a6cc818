#include "core/uwb/height_bias_filter.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

HeightBiasFilter::HeightBiasFilter(const HeightBiasOptions& options, double nominal_height_m)
    : options_(options), nominal_height_m_(nominal_height_m), x_(Eigen::VectorXd::Zero(6)),
      P_(Eigen::MatrixXd::Zero(6, 6)) {
  x_(2) = nominal_height_m;
  // Without height estimation z keeps the nominal height exactly (zero covariance and no
  // process noise: no update moves it).
  if (options_.estimate_height) {
    P_(2, 2) = options_.height_sigma0_m * options_.height_sigma0_m;
    P_(5, 5) = options_.speed_sigma0_mps * options_.speed_sigma0_mps;
  }
}

void HeightBiasFilter::add_anchor(int id, bool calibrated) {
  if (!options_.estimate_bias || anchors_.count(id)) return;
  const Eigen::Index n = x_.size();
  const Eigen::Index added = options_.estimate_scale ? 2 : 1;
  x_.conservativeResize(n + added);
  x_.tail(added).setZero();
  P_.conservativeResize(n + added, n + added);
  P_.bottomRows(added).setZero();
  P_.rightCols(added).setZero();
  const double s0 = calibrated ? options_.calibrated_bias_sigma0_m : options_.bias_sigma0_m;
  P_(n, n) = s0 * s0;
  AnchorState a{n, -1, 0.0, s0, 0};
  if (options_.estimate_scale) {
    a.ks = n + 1;
    const double k0 = calibrated ? options_.calibrated_scale_sigma0 : options_.scale_sigma0;
    P_(a.ks, a.ks) = k0 * k0;
  }
  anchors_[id] = a;
}

void HeightBiasFilter::start(TimeNs t, const Eigen::Vector2d& p_xy, const Eigen::Matrix2d& cov_xy) {
  if (t_ || !enabled() || !p_xy.allFinite() || !cov_xy.allFinite()) return;
  t_ = t;
  x_.head<2>() = p_xy;
  const double s0 = options_.position_sigma0_m, v0 = options_.speed_sigma0_mps;
  P_.topLeftCorner<2, 2>() = cov_xy + Eigen::Matrix2d::Identity() * s0 * s0;
  P_(3, 3) = P_(4, 4) = v0 * v0;
}

void HeightBiasFilter::predict(TimeNs t) {
  if (!t_ || t <= *t_) return;
  const double dt = ns_to_seconds(t - *t_);
  t_ = t;
  // Constant velocity with white acceleration (the discrete Wiener process model) per axis;
  // z only when it is estimated.
  const int axes = options_.estimate_height ? 3 : 2;
  for (int a = 0; a < axes; ++a) {
    x_(a) += x_(3 + a) * dt;
    P_.row(a) += dt * P_.row(3 + a);
    P_.col(a) += dt * P_.col(3 + a);
    const double q = a < 2 ? options_.horizontal_accel_psd : options_.vertical_accel_psd;
    P_(a, a) += q * dt * dt * dt / 3.0;
    P_(a, 3 + a) += q * dt * dt / 2.0;
    P_(3 + a, a) += q * dt * dt / 2.0;
    P_(3 + a, 3 + a) += q * dt;
  }
  if (x_(2) < options_.min_height_m || x_(2) > options_.max_height_m) {
    x_(2) = std::clamp(x_(2), options_.min_height_m, options_.max_height_m);
    x_(5) = 0.0;
  }
  for (auto& [id, a] : anchors_) {
    P_(a.k, a.k) += options_.bias_walk_psd * dt;
    if (a.ks >= 0) P_(a.ks, a.ks) += options_.scale_walk_psd * dt;
  }
}

HeightBiasFilter::Outcome HeightBiasFilter::update(int id, const Eigen::Vector3d& a_inW, double range_m,
                                                   double range_sigma_m) {
  if (!t_ || !std::isfinite(range_m) || !a_inW.allFinite()) return Outcome::skipped;
  const Eigen::Vector3d d = x_.head<3>() - a_inW;
  const double dn = d.norm();
  if (!(dn > 0.05)) return Outcome::skipped;  // on the anchor: no direction
  const auto it = anchors_.find(id);
  const Eigen::Index n = x_.size();
  Eigen::RowVectorXd H = Eigen::RowVectorXd::Zero(n);
  const bool known = it != anchors_.end();
  const double s = known && it->second.ks >= 0 ? x_(it->second.ks) : 0.0;
  H.head<3>() = (1.0 + s) * d.transpose() / dn;
  if (!options_.estimate_height) H(2) = 0.0;
  if (known) H(it->second.k) = 1.0;
  if (known && it->second.ks >= 0) H(it->second.ks) = dn;
  const double b = known ? x_(it->second.k) : 0.0;
  const double nu = range_m - ((1.0 + s) * dn + b);
  Eigen::VectorXd PHt = P_ * H.transpose();
  const double R = range_sigma_m * range_sigma_m;
  double S = H.dot(PHt) + R;
  Outcome out = Outcome::used;
  if (nu > options_.gate_sigma * std::sqrt(S))
    out = Outcome::gated_long;
  else if (nu < -options_.gate_sigma * std::sqrt(S))
    out = Outcome::gated_short;
  if (it != anchors_.end()) {
    AnchorState& a = it->second;
    const double w = options_.nlos_memory;
    a.long_share = (1.0 - w) * a.long_share + w * (out == Outcome::gated_long ? 1.0 : 0.0);
    a.short_run = out == Outcome::gated_short ? a.short_run + 1 : 0;
    if (a.short_run >= options_.short_run_reopen) {
      // HeightBiasOptions::short_run_reopen: the bias is wrong; reopen it (a larger diagonal
      // keeps P positive semi-definite) and take this range.
      P_(a.k, a.k) = std::max(P_(a.k, a.k), a.sigma0_m * a.sigma0_m);
      PHt = P_ * H.transpose();
      S = H.dot(PHt) + R;
      a.short_run = 0;
      ++stats_.bias_reopened;
      out = Outcome::used;
    }
  }
  if (out == Outcome::gated_long) {
    ++stats_.gated_long;
    return out;
  }
  if (out == Outcome::gated_short) {
    ++stats_.gated_short;
    return out;
  }
  // Kalman update, Joseph form (P stays symmetric positive semi-definite).
  const Eigen::VectorXd K = PHt / S;
  x_ += K * nu;
  const Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(n, n) - K * H;
  P_ = I_KH * P_ * I_KH.transpose() + R * K * K.transpose();
  ++stats_.used;
  return out;
}

HeightBiasFilter::Outcome HeightBiasFilter::update_height(double z_m, double sigma_m) {
  if (!t_ || !options_.estimate_height || !std::isfinite(z_m) || !(sigma_m > 0.0) || !std::isfinite(sigma_m))
    return Outcome::skipped;
  const Eigen::Index n = x_.size();
  const double R = sigma_m * sigma_m;
  const double S = P_(2, 2) + R;
  const double nu = z_m - x_(2);
  if (std::abs(nu) > options_.gate_sigma * std::sqrt(S)) {
    ++stats_.heights_gated;
    return nu > 0.0 ? Outcome::gated_long : Outcome::gated_short;
  }
  // H = e_z; Joseph form.
  const Eigen::VectorXd K = P_.col(2) / S;
  x_ += K * nu;
  Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(n, n);
  I_KH.col(2) -= K;
  P_ = I_KH * P_ * I_KH.transpose() + R * K * K.transpose();
  ++stats_.heights_used;
  return Outcome::used;
}

double HeightBiasFilter::height_m() const { return options_.estimate_height && t_ ? x_(2) : nominal_height_m_; }

double HeightBiasFilter::height_sigma_m() const { return std::sqrt(std::max(0.0, P_(2, 2))); }

double HeightBiasFilter::bias_m(int id) const {
  const auto it = anchors_.find(id);
  return it == anchors_.end() ? 0.0 : x_(it->second.k);
}

double HeightBiasFilter::scale(int id) const {
  const auto it = anchors_.find(id);
  return it == anchors_.end() || it->second.ks < 0 ? 1.0 : 1.0 + x_(it->second.ks);
}

double HeightBiasFilter::scale_sigma(int id) const {
  const auto it = anchors_.find(id);
  return it == anchors_.end() || it->second.ks < 0 ? 0.0 : std::sqrt(std::max(0.0, P_(it->second.ks, it->second.ks)));
}

double HeightBiasFilter::bias_sigma_m(int id) const {
  const auto it = anchors_.find(id);
  return it == anchors_.end() ? 0.0 : std::sqrt(std::max(0.0, P_(it->second.k, it->second.k)));
}

bool HeightBiasFilter::nlos(int id) const {
  const auto it = anchors_.find(id);
  return it != anchors_.end() && it->second.long_share > options_.nlos_share;
}

}  // namespace luxloc
