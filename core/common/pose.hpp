#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>

#include "core/common/time.hpp"

namespace luxloc {

// A fused pose as written to the outputs (SPEC.md "Pose output").
struct PoseEstimate {
  TimeNs t = 0;
  Eigen::Vector3d p_BinW = Eigen::Vector3d::Zero();
  // NaN when unknown (no IMU: the attitude filter never aligned), never a made-up 0.
  double yaw = std::numeric_limits<double>::quiet_NaN();    // rad, CCW from east
  double roll = std::numeric_limits<double>::quiet_NaN();   // rad (from the attitude filter)
  double pitch = std::numeric_limits<double>::quiet_NaN();  // rad
  double sigma_x = std::numeric_limits<double>::quiet_NaN();
  double sigma_y = std::numeric_limits<double>::quiet_NaN();
  double sigma_yaw = std::numeric_limits<double>::quiet_NaN();  // rad, 1 sigma of the fused yaw
  double sigma_z = std::numeric_limits<double>::quiet_NaN();    // m; NaN: z is the nominal height, not estimated
  double n_eff = std::numeric_limits<double>::quiet_NaN();
  int leds = 0;             // LEDs decoded in the last frame
  std::string mode = "";    // e.g. "fused", "imu-only", "init"
  // The motion mode the prediction used up to this pose (issue 16: the mode over time):
  // walking (gait), moving (strapdown: no steps), still (zero velocity), constant-velocity
  // (no IMU, or --motion cv); empty when unknown.
  std::string motion = "";
  // Set by the pipeline: when the newest input this pose used arrived in its source
  // thread (steady clock, ns; 0 = unknown), and the age of that input when the pose was
  // handed to the sinks (s; NaN = unknown). Not written to the pose files (runs stay
  // reproducible); the live views show it.
  std::int64_t input_arrival_ns = 0;
  double latency_s = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace luxloc
