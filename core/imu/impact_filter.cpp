#include "core/imu/impact_filter.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace luxloc {

const std::vector<ImpactFilter::Sample>& ImpactFilter::update(TimeNs t, double a_mps2) {
  out_.clear();
  if (!std::isfinite(a_mps2)) return out_;
  const TimeNs t_last = !held_.empty() ? held_.back().first : !recent_.empty() ? recent_.back().first : t - 1;
  if (t <= t_last) return out_;  // time must advance
  // The reference is the last sample handed on, and while an impact lasts the one before it.
  // Within an impact the band is max_jump about the reference; to start one, a sample must
  // also jump faster than max_jerk (at rates above 100 Hz a spike's edge moves by less than
  // max_jump a sample, and would creep in).
  double band = options_.max_jump_mps2;
  if (held_.empty() && !recent_.empty()) {
    reference_ = recent_.back().second;
    band = std::min(band, options_.max_jerk_mps3 * ns_to_seconds(t - recent_.back().first));
  }
  const bool jump = !recent_.empty() && options_.max_jump_mps2 > 0.0 && std::abs(a_mps2 - reference_) > band;
  if (held_.empty() && !jump) {
    out_.emplace_back(t, a_mps2);
  } else {
    if (held_.empty()) {
      // The samples handed on within margin may carry the spike's leading edge (inside the
      // band): the fit takes those before.
      current_ = reference_;
      const TimeNs edge = t - seconds_to_ns(options_.margin_s);
      auto older = recent_.rbegin();
      while (older != recent_.rend() && older->first > edge) ++older;
      before_.assign(recent_.begin(), older.base());
    }
    held_.emplace_back(t, a_mps2);
    if (jump) t_back_ = -1;
    else if (t_back_ < 0) t_back_ = t;
    if (ns_to_seconds(t - held_.front().first) >= options_.max_hold_s + options_.margin_s + options_.fit_window_s) {
      release(false);  // a lasting change, not an impact
    } else if (t_back_ >= 0 && ns_to_seconds(t - t_back_) >= options_.margin_s + options_.fit_window_s) {
      release(true);
    } else {
      return out_;
    }
  }
  for (const Sample& s : out_) recent_.push_back(s);
  const TimeNs keep = seconds_to_ns(options_.margin_s + options_.fit_window_s);
  while (recent_.size() > 1 && recent_.back().first - recent_.front().first > keep) recent_.pop_front();
  current_ = out_.back().second;
  return out_;
}

void ImpactFilter::release(bool repair) {
  // The clean samples after the impact: those from margin after it came back; the fit takes
  // them and those before it.
  const TimeNs clean_from = t_back_ + seconds_to_ns(options_.margin_s);
  const TimeNs t0 = held_.front().first;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  if (repair) {
    std::vector<Sample> fit = before_;
    for (const Sample& s : held_)
      if (s.first >= clean_from) fit.push_back(s);
    repair = fit.size() >= 3 && fit.front().first < t0;
    if (repair) {
      // a(t) ~ c0 + c1 u + c2 u^2, u in seconds from the first held sample.
      Eigen::MatrixXd A(static_cast<Eigen::Index>(fit.size()), 3);
      Eigen::VectorXd b(static_cast<Eigen::Index>(fit.size()));
      for (std::size_t i = 0; i < fit.size(); ++i) {
        const double u = ns_to_seconds(fit[i].first - t0);
        A.row(static_cast<Eigen::Index>(i)) << 1.0, u, u * u;
        b(static_cast<Eigen::Index>(i)) = fit[i].second;
      }
      c = A.colPivHouseholderQr().solve(b);
      repair = c.allFinite();
    }
  }
  for (const Sample& s : held_) {
    if (!repair || s.first >= clean_from) {
      out_.push_back(s);
      continue;
    }
    const double u = ns_to_seconds(s.first - t0);
    out_.emplace_back(s.first, c(0) + u * (c(1) + u * c(2)));
    ++repaired_;
  }
  held_.clear();
  before_.clear();
  t_back_ = -1;
}

}  // namespace luxloc
