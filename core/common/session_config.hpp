#pragma once
// Session-wide settings from session.yaml (SPEC.md "Session folder").
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "core/common/sensor_limits.hpp"

namespace luxloc {

struct UwbAnchor {
  int id = 0;
  Eigen::Vector3d p_inW = Eigen::Vector3d::Zero();
};

struct SessionConfig {
  double device_height_m = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  std::vector<UwbAnchor> anchors;
  SensorLimits limits;  // `sensor_limits`: the sensors' plausible ranges (playback)
  // File names (relative to the session folder) where they differ from SPEC's defaults.
  std::string imu_file = "imu.csv";
  std::string frames_file = "frames.csv";
  std::string uwb_file = "uwb.csv";
  std::string fixes_file = "fixes.csv";
  std::string odom_file = "odom.csv";
  std::string groundtruth_file = "groundtruth.csv";
  std::string ledmap_file = "ledmap.yaml";
  std::string camera_file = "camera.yaml";
};

}  // namespace luxloc
