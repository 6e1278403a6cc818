#pragma once
// Pedestrian dead reckoning (SEEDS.md A, S1): every detected step k yields a length l_k and
// a heading alpha_k, and X_{k+1} = X_k + l_k cos(alpha_k), Y_{k+1} = Y_k + l_k sin(alpha_k).
// Feed it every IMU sample with the attitude of that sample (from MahonyFilter); take the
// steps with pop_step(). Each step carries its own 1-sigma length and heading uncertainty,
// which a particle filter uses as process noise.
//
// Heading: the circular mean of the device yaw over the step (the body sways left and right
// every step) plus heading_offset_rad (device carried not pointing along the walk).
// Latency: a step is known StepDetectorOptions::min_interval_s after its heel strike; Step::t
// is the heel strike itself (earlier than the sample that produced it).
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <optional>

#include "core/common/samples.hpp"
#include "core/imu/gravity_window.hpp"
#include "core/imu/impact_filter.hpp"
#include "core/imu/step_detector.hpp"
#include "core/imu/step_length.hpp"

namespace luxloc {

struct PdrOptions {
  ImpactFilterOptions impacts;  // heel-strike spikes out of the vertical acceleration first
  StepDetectorOptions detector;
  StepLengthOptions length;
  double heading_offset_rad = 0.0;   // walking direction minus device yaw
  double heading_sigma_rad = 0.035;  // ~2 deg per step: sway, attitude noise
  double gravity = 9.80665;
  // A log without a gyroscope (gx, gy, gz exactly 0 on every sample for this long: a real
  // gyroscope's noise never reads 0, 0, 0 twice in a row, let alone while the accelerometer
  // shows steps) takes the vertical from `gravity_window` instead of the attitude filter.
  double gyro_absent_after_s = 1.0;
  GravityWindowOptions gravity_window;
};

struct Step {
  TimeNs t = 0;                    // heel strike
  double length_m = 0.0;           // l_k
  double heading_rad = 0.0;        // alpha_k, CCW from east (world ENU)
  double length_sigma_m = 0.0;
  double heading_sigma_rad = 0.0;
  double interval_s = 0.0;         // since the previous step (0 after a stop)
  double swing_mps2 = 0.0;         // the detector's peak - valley (GaitGate: are steps alike)
};

class PedestrianDeadReckoning {
 public:
  explicit PedestrianDeadReckoning(const PdrOptions& options = {});

  // One IMU sample and the attitude at its time (R_BtoW: body FLU -> world ENU).
  void update(const ImuSample& s, const Eigen::Matrix3d& R_BtoW);
  // End of the stream: emits the last step if its peak qualifies (it would otherwise wait for
  // confirmation that never comes).
  void finish();
  // Oldest step not yet taken, if any.
  std::optional<Step> pop_step();

  // Dead-reckoned position: the sum of all steps from `origin` (S1 without fixes).
  const Eigen::Vector2d& position() const { return p_inW_; }
  void set_position(const Eigen::Vector2d& p_inW) { p_inW_ = p_inW; }
  std::uint64_t step_count() const { return count_; }
  double distance_m() const { return distance_m_; }
  const PdrOptions& options() const { return options_; }
  // The vertical acceleration (world up, gravity removed) of the last sample without
  // heel-strike impacts: during one the value before it (ImpactFilter::current).
  double vertical_mps2() const { return impacts_.current(); }
  // Samples of heel-strike impacts replaced (ImpactFilter).
  std::uint64_t impact_samples() const { return impacts_.repaired(); }
  // True while the gyroscope reads exactly zero (see PdrOptions::gyro_absent_after_s).
  bool gyro_absent() const { return gyro_absent_; }
  // Seconds of the stream spent with gyro_absent() (sample intervals ending in such a sample).
  double gyro_absent_s() const { return ns_to_seconds(gyro_absent_ns_); }

 private:
  double mean_heading(TimeNs from, TimeNs to) const;
  void add_step(const DetectedStep& d);

  PdrOptions options_;
  ImpactFilter impacts_;
  StepDetector detector_;
  StepLengthModel length_;
  std::deque<std::pair<TimeNs, double>> yaw_history_;  // last few seconds of device yaw
  std::deque<Step> pending_;
  GravityWindow gravity_;
  std::optional<TimeNs> last_gyro_t_;  // last sample with a non-zero gyro (or the first sample)
  bool gyro_absent_ = false;
  TimeNs gyro_absent_ns_ = 0;
  Eigen::Vector2d p_inW_ = Eigen::Vector2d::Zero();
  std::uint64_t count_ = 0;
  double distance_m_ = 0.0;
};

}  // namespace luxloc
