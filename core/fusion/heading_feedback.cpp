#include "core/fusion/heading_feedback.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace luxloc {

std::optional<HeadingFeedback::Transfer> HeadingFeedback::update(TimeNs t, double offset_rad, double sigma_rad) {
  if (!options_.enabled || !std::isfinite(offset_rad) || !std::isfinite(sigma_rad) ||
      sigma_rad > options_.max_sigma_rad)
    return std::nullopt;
  Transfer tr;
  tr.dyaw_rad = std::clamp(offset_rad, -options_.max_step_rad, options_.max_step_rad);
  if (t_last_) {
    const double dt = ns_to_seconds(t - *t_last_);
    if (dt > 0.0 && dt <= options_.max_interval_s && options_.bias_tau_s > 0.0) {
      // The offset that built up since the last transfer, at most max_rate of drift.
      const double bound = options_.max_rate_rps * dt;
      tr.drate_rps = std::clamp(tr.dyaw_rad, -bound, bound) / options_.bias_tau_s;
    }
  }
  t_last_ = t;
  learnt_rate_ += tr.drate_rps;
  ++transfers_;
  return tr;
}

double HeadingFeedback::since_fix_s(TimeNs t) const {
  return t_last_ ? std::max(0.0, ns_to_seconds(t - *t_last_)) : std::numeric_limits<double>::infinity();
}

void HeadingObserver::predict(double dt, double drift_s, double bound_rad) {
  if (!(dt > 0.0) || !std::isfinite(dt)) return;
  offset_ *= noise_.propagate(var_, dt, drift_s, bound_rad);
  // Never more uncertain than "anywhere": keeps the gain meaningful after a long outage.
  var_ = std::min(var_, 1.0);
}

bool HeadingObserver::correct(const YawMeasurement& m, double gate_sigma) {
  if (!std::isfinite(m.offset_rad) || !(m.sigma_rad > 0.0)) {
    ++rejected_;
    return false;
  }
  const double r = m.sigma_rad * m.sigma_rad;
  const double innov = std::remainder(m.offset_rad - offset_, 2.0 * 3.14159265358979323846);
  if (innov * innov > gate_sigma * gate_sigma * (var_ + r)) {
    ++rejected_;
    return false;
  }
  const double k = var_ / (var_ + r);
  offset_ += k * innov;
  var_ = std::max((1.0 - k) * var_, noise_.min_sigma_rad * noise_.min_sigma_rad);  // scalar: Joseph = short form
  return true;
}

double HeadingObserver::sigma_rad() const { return std::sqrt(std::max(0.0, var_)); }

}  // namespace luxloc
