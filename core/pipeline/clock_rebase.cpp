#include "core/pipeline/clock_rebase.hpp"

#include <cmath>

namespace luxloc {

// Weight of one sample in the running mean lag: a time constant of 32 samples (0.3 s of a
// 100 Hz IMU, 1 s of a 30 fps camera) follows a latency that drifts (a simulator or driver
// falling behind under load) but not a step.
constexpr double kLagWeight = 1.0 / 32.0;

TimeNs ClockRebase::apply(TimeNs t, TimeNs arrival) {
  jumped_ = false;
  const TimeNs corrected = t + correction_;
  const double lag = static_cast<double>(arrival - corrected);
  if (!have_lag_) {
    have_lag_ = true;
    mean_lag_ = lag;
    return corrected;
  }
  const double step = lag - mean_lag_;
  if (std::abs(step) > static_cast<double>(threshold_)) {
    // The stamp moved by -step against the arrival clock: take that back.
    const TimeNs fix = static_cast<TimeNs>(std::llround(step));
    correction_ += fix;
    last_jump_ = -fix;
    jumped_ = true;
    ++jumps_;
    return corrected + fix;
  }
  mean_lag_ += kLagWeight * step;
  return corrected;
}

}  // namespace luxloc
