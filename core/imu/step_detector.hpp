#pragma once
// Step detection from the vertical acceleration (SEEDS.md A, S1: "each step k the IMU
// package yields..."). The specific force rotated into the world, minus g, is smoothed by a
// short moving average; a heel strike is the peak of that signal. A peak counts as a step
// when it rises above min_peak, swings at least min_swing above the lowest value since the
// previous step, and is the highest within min_interval (double peaks of one heel strike
// merge). Steps are confirmed min_interval after their peak, so they arrive that late.
#include <cstdint>
#include <deque>
#include <optional>

#include "core/common/time.hpp"

namespace luxloc {

struct StepDetectorOptions {
  double smoothing_s = 0.1;      // moving-average width on the vertical acceleration
  double min_peak_mps2 = 0.3;    // a heel-strike peak exceeds g by at least this
  double min_swing_mps2 = 0.8;   // peak minus the valley before it (m/s^2)
  double min_interval_s = 0.3;   // steps closer than this are one (cadence <= 3.3 Hz)
  double max_interval_s = 2.0;   // longer gaps: the walker stopped (no cadence across them)
};

struct DetectedStep {
  TimeNs t = 0;                 // time of the peak (heel strike)
  double peak_mps2 = 0.0;       // smoothed vertical acceleration at the peak
  double valley_mps2 = 0.0;     // lowest smoothed value between the previous step and this one
  double interval_s = 0.0;      // since the previous step; 0 for the first after a stop
  double swing() const { return peak_mps2 - valley_mps2; }
};

class StepDetector {
 public:
  explicit StepDetector(const StepDetectorOptions& options = {});

  // Vertical acceleration in the world (up positive, gravity removed), in time order.
  // Returns a step when one is confirmed (its t lies min_interval in the past).
  std::optional<DetectedStep> update(TimeNs t, double a_up_mps2);
  // End of the stream: the last peak, if it qualifies, without waiting for confirmation.
  std::optional<DetectedStep> flush();
  std::uint64_t steps() const { return steps_; }
  const StepDetectorOptions& options() const { return options_; }

 private:
  struct Candidate {
    TimeNs t;
    double y, valley;
  };
  std::optional<DetectedStep> detect(TimeNs t, double y);
  std::optional<DetectedStep> confirm();

  StepDetectorOptions options_;
  // Moving average (time-windowed): raw samples and their running sum.
  std::deque<std::pair<TimeNs, double>> raw_;
  double raw_sum_ = 0.0;
  // Last two smoothed values, for the local-maximum test.
  int n_smoothed_ = 0;
  TimeNs t_prev_ = 0;
  double y_prev_ = 0.0, y_prev2_ = 0.0;
  double valley_ = 0.0;     // min since the last step
  double post_min_ = 0.0;   // min since the candidate
  std::optional<Candidate> cand_;
  std::optional<TimeNs> last_step_t_;
  std::uint64_t steps_ = 0;
};

}  // namespace luxloc
