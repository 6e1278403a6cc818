#include "core/fusion/innovation_bias.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

void InnovationBias::add(TimeNs t, const Eigen::Vector2d& nu, const Eigen::Matrix2d& S) {
  if (!options_.enabled || !nu.allFinite() || !S.allFinite() || !(S(0, 0) > 0.0) || !(S(1, 1) > 0.0)) return;
  // Older samples fade with their age (a fix out of order counts as new: no growth).
  double w = 0.0;
  if (t_last_) {
    const double dt = std::max(0.0, ns_to_seconds(t - *t_last_));
    w = options_.time_constant_s > 0.0 ? std::exp(-dt / options_.time_constant_s) : 0.0;
  }
  if (!t_last_ || t > *t_last_) t_last_ = t;
  w_sum_ = w * w_sum_ + 1.0;
  w2_sum_ = w * w * w2_sum_ + 1.0;
  nu_sum_ = w * nu_sum_ + nu;
  s_sum_ = w * s_sum_ + S.diagonal();
  const double n_eff = w_sum_ * w_sum_ / w2_sum_;
  const Eigen::Vector2d m = nu_sum_ / w_sum_;
  const Eigen::Vector2d var_m = s_sum_ / w_sum_ / n_eff;
  for (int a = 0; a < 2; ++a) extra_(a) = std::max(0.0, m(a) * m(a) - options_.excess_share * var_m(a));
}

Eigen::Vector2d InnovationBias::mean_innovation() const {
  return w_sum_ > 0.0 ? Eigen::Vector2d(nu_sum_ / w_sum_) : Eigen::Vector2d::Zero();
}

void InnovationBias::reset() { *this = InnovationBias(options_); }

}  // namespace luxloc
