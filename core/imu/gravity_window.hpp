#pragma once
// The vertical of a device without a gyroscope: the mean of the accelerometer over the last
// window_s seconds points up in the body frame (the walk's accelerations average out over a
// stride; gravity does not). Used by PedestrianDeadReckoning when an IMU log carries no
// gyroscope (gx, gy, gz exactly 0, e.g. the accelerometer-only phone walks of
// ../shared/realdata/phone_steps): the attitude filter cannot then follow a device that
// tilts in a bag or a pocket, and rejects the accelerometer whenever it is off g, so its
// vertical goes stale. Causal (real time): the mean lags by window_s / 2, which a device's
// slow re-orientation in a bag or pocket tolerates.
#include <Eigen/Core>
#include <deque>
#include <utility>

#include "core/common/time.hpp"

namespace luxloc {

struct GravityWindowOptions {
  // 2 s: longer than one stride (two steps) at the slowest cadence the simulator's walker
  // population draws (1.4 Hz steps: a 1.43 s stride), so a whole gait cycle averages out.
  // Chosen from that bound, not fitted to any recording.
  double window_s = 2.0;
};

class GravityWindow {
 public:
  explicit GravityWindow(const GravityWindowOptions& options = {});
  // One accelerometer sample (body frame, m/s^2), in time order; others are ignored.
  void add(TimeNs t, const Eigen::Vector3d& acc_inB);
  // Unit vector up in the body frame; zero before the first finite sample.
  Eigen::Vector3d up_inB() const;

 private:
  GravityWindowOptions options_;
  std::deque<std::pair<TimeNs, Eigen::Vector3d>> samples_;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  unsigned long long adds_ = 0;
};

}  // namespace luxloc
