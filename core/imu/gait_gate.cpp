#include "core/imu/gait_gate.hpp"

#include <algorithm>

namespace luxloc {

GaitGate::GaitGate(const GaitGateOptions& options) : options_(options) {}

bool GaitGate::add(double interval_s, double swing_mps2) {
  if (confirmed_) return true;
  if (!(interval_s > 0.0)) recent_.clear();  // after a stop: a new run of steps
  recent_.emplace_back(interval_s, swing_mps2);
  while (recent_.size() > options_.steps) recent_.pop_front();
  if (recent_.size() < options_.steps || options_.steps < 2) return false;
  double i_lo = 1e9, i_hi = 0.0, s_lo = 1e9, s_hi = 0.0;
  for (std::size_t k = 0; k < recent_.size(); ++k) {
    s_lo = std::min(s_lo, recent_[k].second);
    s_hi = std::max(s_hi, recent_[k].second);
    if (k == 0) continue;  // its interval reaches back before the run
    i_lo = std::min(i_lo, recent_[k].first);
    i_hi = std::max(i_hi, recent_[k].first);
  }
  const bool in_band = i_lo >= 1.0 / options_.max_hz && i_hi <= 1.0 / options_.min_hz;
  const bool regular = i_hi <= options_.max_interval_ratio * i_lo;
  const bool alike = s_lo > 0.0 && s_hi <= options_.max_swing_ratio * s_lo;
  confirmed_ = in_band && regular && alike;
  return confirmed_;
}

}  // namespace luxloc
