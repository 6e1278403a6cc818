#pragma once
// Session-wide settings from session.yaml (SPEC.md "Session folder").
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/common/sensor_limits.hpp"

namespace luxloc {

struct UwbAnchor {
  int id = 0;
  Eigen::Vector3d p_inW = Eigen::Vector3d::Zero();
  // The anchor's range calibration (issue 16, `luxloc calib uwb`): a line-of-sight range
  // reads measured = scale * true + bias_m (antenna delay: bias, clock: scale). Optional in
  // session.yaml; the defaults leave ranges as measured.
  double bias_m = 0.0;
  double scale = 1.0;
  // The range this anchor's calibration makes of a measured one: (measured - bias) / scale.
  double corrected_range(double measured_m) const { return (measured_m - bias_m) / scale; }
};

// A known start (`run --start X,Y[,YAW]`, session.yaml `start: {x, y, yaw, sigma_m}`): the
// filter starts there without an absolute source (dead reckoning from a known pose).
struct StartPose {
  Eigen::Vector2d p_inW = Eigen::Vector2d::Zero();
  double yaw = std::numeric_limits<double>::quiet_NaN();  // rad, CCW from east; NaN: the AHRS's
  double sigma_m = 0.1;                                   // 1 sigma per axis
};

struct SessionConfig {
  double device_height_m = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  std::vector<UwbAnchor> anchors;
  std::optional<StartPose> start;
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
