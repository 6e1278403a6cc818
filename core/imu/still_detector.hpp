#pragma once
// Is the device at rest? Over a sliding window the gyro and the accelerometer must both be
// quiet (small per-axis spread), the mean rate small and the mean specific force close to
// g. At rest the mean gyro reading is the gyro bias (SEEDS.md C.3's ki term learns it only
// slowly, and never about the vertical without a magnetometer), so the window means are
// exposed for a direct bias estimate.
#include <Eigen/Core>
#include <cstdint>
#include <deque>

#include "core/common/samples.hpp"

namespace luxloc {

struct StillOptions {
  double window_s = 0.4;                 // samples spanning this long decide
  double gyro_std_max_rps = 0.015;       // per-axis standard deviation of the rate (~0.9 deg/s)
  double gyro_mean_max_rps = 0.05;       // |mean rate|: bias plus slow motion (~3 deg/s)
  double acc_std_max_mps2 = 0.12;        // per-axis standard deviation of the specific force
  double acc_norm_tolerance_mps2 = 0.4;  // | |mean acc| - g |
  double gravity = 9.80665;
};

class StillDetector {
 public:
  explicit StillDetector(const StillOptions& options = {});

  // Adds a sample (non-finite ones are ignored) and returns still().
  bool update(const ImuSample& s);
  void reset();

  bool still() const { return still_; }
  // Time since the window first qualified as still (0 when moving).
  double still_duration_s() const;
  // Means over the current window (valid once a window has been filled).
  Eigen::Vector3d mean_gyro() const;
  Eigen::Vector3d mean_acc() const;
  // Mean gyro reading over the whole current still run (the window that first qualified
  // plus every sample since): the at-rest bias estimate, its noise falling as 1/sqrt(n).
  Eigen::Vector3d still_mean_gyro() const;
  std::size_t still_samples() const { return still_ ? run_n_ : 0; }
  // Samples in the window and the time it spans.
  std::size_t window_size() const { return window_.size(); }
  const StillOptions& options() const { return options_; }

 private:
  struct Entry {
    TimeNs t;
    Eigen::Vector3d gyro, acc;
  };
  void recompute_sums();
  bool evaluate() const;

  StillOptions options_;
  std::deque<Entry> window_;
  Eigen::Vector3d sum_g_ = Eigen::Vector3d::Zero(), sum_gg_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_a_ = Eigen::Vector3d::Zero(), sum_aa_ = Eigen::Vector3d::Zero();
  std::uint64_t pops_since_recompute_ = 0;
  Eigen::Vector3d run_sum_g_ = Eigen::Vector3d::Zero();
  std::size_t run_n_ = 0;
  bool still_ = false;
  TimeNs still_since_ = 0, t_last_ = 0;
};

}  // namespace luxloc
