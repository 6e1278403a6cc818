#pragma once
// Timestamped sensor samples: what sources emit and the fusion stage consumes.
// Frames follow SPEC.md: world ENU, body FLU, SI units, t on the internal ns timeline.
#include <Eigen/Core>
#include <limits>
#include <opencv2/core/mat.hpp>
#include <string>
#include <variant>

#include "core/common/time.hpp"

namespace luxloc {

struct ImuSample {
  TimeNs t = 0;
  Eigen::Vector3d acc_inB = Eigen::Vector3d::Zero();   // specific force, m/s^2 (+9.81 z at rest)
  Eigen::Vector3d gyro_inB = Eigen::Vector3d::Zero();  // rad/s
  Eigen::Vector3d mag_inB = Eigen::Vector3d::Zero();   // microtesla, valid when has_mag
  bool has_mag = false;
};

struct FrameSample {
  TimeNs t = 0;       // start of exposure of row 0
  cv::Mat gray;       // CV_8UC1, sensor orientation (rows = rolling-shutter readout order)
  std::string file;   // where it came from (for messages); may be empty for live frames
};

struct UwbSample {
  TimeNs t = 0;
  int anchor = -1;
  double range_m = 0.0;  // measured 3-D distance anchor -> device
  double aoa_rad = std::numeric_limits<double>::quiet_NaN();  // world bearing of device from anchor
  // Anchor position as reported by the device itself (DWM1001 `lec` lines), NaN when the
  // source does not know it (then session.yaml's anchors apply).
  Eigen::Vector3d p_AinW = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

struct FixSample {
  TimeNs t = 0;
  Eigen::Vector2d p_inW = Eigen::Vector2d::Zero();
  double sigma_m = std::numeric_limits<double>::quiet_NaN();  // NaN: unknown, use default
};

struct OdomSample {
  TimeNs t = 0;
  double dist_m = 0.0;
  double dyaw_rad = 0.0;
};

using SensorData = std::variant<ImuSample, FrameSample, UwbSample, FixSample, OdomSample>;

// One item on a source queue. `source` indexes the pipeline's source list.
struct Sample {
  TimeNs t = 0;
  int source = 0;
  SensorData data;
};

inline TimeNs sample_time(const SensorData& d) {
  return std::visit([](const auto& s) { return s.t; }, d);
}

}  // namespace luxloc
