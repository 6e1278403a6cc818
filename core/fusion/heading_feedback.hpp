#pragma once
// Heading in the fusion (issue 11, part 2). The filters carry the yaw offset e of the
// attitude filter (true yaw = AHRS yaw + e; core/filter/heading_noise.hpp): the particle
// filter one per particle, the EKF path this file's HeadingObserver (a scalar Kalman filter
// on e, corrected by the camera's direct yaw from two or more LEDs). HeadingFeedback then
// moves a well-determined e into the AHRS: its yaw turns by e, the filter's offsets drop by
// e (the absolute heading is unchanged), and the offsets that keep coming back between
// transfers are a gyro z bias the AHRS has not learnt: a PI loop adds e / bias_tau_s to its
// integrated vertical rate. So the camera (and whatever else fixes e) learns the gyro bias
// in seconds while the lights are in view, and dead reckoning through a blackout starts
// from it. Roll and pitch stay with the AHRS.
#include <cstdint>
#include <optional>

#include "core/common/time.hpp"
#include "core/filter/heading_noise.hpp"

namespace luxloc {

// A direct measurement of the yaw offset e (camera geometry of two or more LEDs).
struct YawMeasurement {
  TimeNs t = 0;
  double offset_rad = 0.0;  // true yaw - AHRS yaw
  double sigma_rad = 0.0;   // 1 sigma
};

struct HeadingFeedbackOptions {
  bool enabled = true;
  // Move e into the AHRS only when the filter knows it to this (1 sigma): 1.5 deg, well
  // above the two-LED geometry's ~0.2-0.5 deg and below the AHRS's own magnetometer error
  // of 2-3 deg in a disturbed field (docs/IMU.md), so a transfer always improves the AHRS.
  double max_sigma_rad = 0.026;
  // PI integral time constant of the gyro z bias (s): a residual bias b shows as an offset
  // b dt at every transfer; adding offset / tau to the rate converges with time constant
  // tau. 8 s: tuned on sim seeds 1-10 (consumer grade, 1 deg/s z bias, walk with LEDs):
  // 4 s rang (the offsets carry the filter's own noise), 20 s left 0.3 deg/s after a minute.
  double bias_tau_s = 8.0;
  // Offsets count towards the bias only when the previous transfer is this recent (a long
  // gap's offset is mostly the gap's drift plus the noise of two estimates), and only up
  // to max_rate_rps of drift per second: the first transfer after start or after a gap
  // carries the AHRS's alignment error, which is not a rate. 2 deg/s: the largest bias a
  // consumer gyro has after its factory calibration (issue 11: "up to 1 deg/s per axis").
  double max_interval_s = 1.0;
  double max_rate_rps = 0.035;
  // Never correct the AHRS by more than this in one transfer (a wrong association would
  // otherwise throw the attitude around): 0.35 rad (20 deg).
  double max_step_rad = 0.35;
  // For this long after a transfer the AHRS's magnetometer is held (MahonyFilter::
  // hold_magnetometer): the fused heading is the better reference. 2 s: a few missed
  // frames do not hand the heading back to a disturbed field; a blackout does.
  double mag_hold_s = 2.0;
};

class HeadingFeedback {
 public:
  explicit HeadingFeedback(const HeadingFeedbackOptions& options = {}) : options_(options) {}

  struct Transfer {
    double dyaw_rad = 0.0;   // turn the AHRS by this; the filter's offsets drop by it
    double drate_rps = 0.0;  // add this to the AHRS's vertical rate (gyro bias)
  };
  // The filter's offset estimate (mean, sigma) after a heading observation at t: the
  // transfer to apply, or nullopt when e is not well determined.
  std::optional<Transfer> update(TimeNs t, double offset_rad, double sigma_rad);
  // Seconds since the last transfer at t (the heading's drift clock; infinity: never).
  double since_fix_s(TimeNs t) const;
  double learnt_rate_rps() const { return learnt_rate_; }
  const HeadingFeedbackOptions& options() const { return options_; }  // sum of drate so far
  std::uint64_t transfers() const { return transfers_; }

 private:
  HeadingFeedbackOptions options_;
  std::optional<TimeNs> t_last_;
  double learnt_rate_ = 0.0;
  std::uint64_t transfers_ = 0;
};

// The EKF path's heading state: a scalar Kalman filter on e with the particles' process
// model (HeadingNoise: a random walk plus the drift of a residual gyro bias).
class HeadingObserver {
 public:
  explicit HeadingObserver(const HeadingNoise& noise = {}) : noise_(noise), var_(noise.sigma0_rad * noise.sigma0_rad) {}
  // Over dt seconds, drift_s after the last heading fix.
  void predict(double dt, double drift_s, double bound_rad = 0.0);
  // Gated at gate_sigma; false when refused.
  bool correct(const YawMeasurement& m, double gate_sigma = 4.0);
  void shift(double delta_rad) { offset_ -= delta_rad; }
  double offset_rad() const { return offset_; }
  double sigma_rad() const;
  std::uint64_t rejected() const { return rejected_; }

 private:
  HeadingNoise noise_;
  double offset_ = 0.0, var_;
  std::uint64_t rejected_ = 0;
};

}  // namespace luxloc
