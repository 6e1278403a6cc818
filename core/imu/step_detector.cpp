#include "core/imu/step_detector.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

StepDetector::StepDetector(const StepDetectorOptions& options) : options_(options) {}

std::optional<DetectedStep> StepDetector::update(TimeNs t, double a_up_mps2) {
  if (!std::isfinite(a_up_mps2)) return std::nullopt;
  if (!raw_.empty() && t <= raw_.back().first) return std::nullopt;  // time must advance
  raw_.emplace_back(t, a_up_mps2);
  raw_sum_ += a_up_mps2;
  const TimeNs width = seconds_to_ns(options_.smoothing_s);
  while (raw_.size() > 1 && t - raw_.front().first > width) {
    raw_sum_ -= raw_.front().second;
    raw_.pop_front();
  }
  // The average stands for the middle of its window (no phase lag in the peak time).
  const double y = raw_sum_ / static_cast<double>(raw_.size());
  const TimeNs t_mid = raw_.front().first + (t - raw_.front().first) / 2;
  return detect(t_mid, y);
}

std::optional<DetectedStep> StepDetector::detect(TimeNs t, double y) {
  std::optional<DetectedStep> out;
  if (n_smoothed_ == 0) valley_ = post_min_ = y;
  valley_ = std::min(valley_, y);
  post_min_ = std::min(post_min_, y);
  const TimeNs min_interval = seconds_to_ns(options_.min_interval_s);

  // Local maximum at the previous smoothed sample?
  if (n_smoothed_ >= 2 && y_prev_ > y_prev2_ && y_prev_ >= y) {
    const bool spaced = !last_step_t_ || t_prev_ - *last_step_t_ >= min_interval;
    if (spaced && (!cand_ || y_prev_ > cand_->y)) {
      cand_ = Candidate{t_prev_, y_prev_, valley_};
      post_min_ = y;
    }
  }
  if (cand_ && t - cand_->t >= min_interval) out = confirm();
  y_prev2_ = y_prev_;
  y_prev_ = y;
  t_prev_ = t;
  ++n_smoothed_;
  return out;
}

std::optional<DetectedStep> StepDetector::confirm() {
  std::optional<DetectedStep> out;
  if (cand_->y >= options_.min_peak_mps2 && cand_->y - cand_->valley >= options_.min_swing_mps2) {
    DetectedStep s;
    s.t = cand_->t;
    s.peak_mps2 = cand_->y;
    s.valley_mps2 = cand_->valley;
    const double interval = last_step_t_ ? ns_to_seconds(cand_->t - *last_step_t_) : 0.0;
    s.interval_s = interval <= options_.max_interval_s ? interval : 0.0;
    last_step_t_ = cand_->t;
    valley_ = post_min_;  // the valley before the next step starts after this peak
    ++steps_;
    out = s;
  }
  cand_.reset();
  return out;
}

std::optional<DetectedStep> StepDetector::flush() {
  // The last smoothed sample may itself be the peak (no sample after it yet).
  if (n_smoothed_ >= 2 && y_prev_ > y_prev2_) {
    const bool spaced = !last_step_t_ || t_prev_ - *last_step_t_ >= seconds_to_ns(options_.min_interval_s);
    if (spaced && (!cand_ || y_prev_ > cand_->y)) cand_ = Candidate{t_prev_, y_prev_, valley_};
  }
  if (!cand_) return std::nullopt;
  return confirm();
}

}  // namespace luxloc
