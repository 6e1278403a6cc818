#pragma once
// `luxloc calib imu`: IMU calibration from a log (SEEDS.md C.4).
// 1. Static segments: runs of samples the StillDetector calls still, at least
//    min_segment_s long (the detector's window is trimmed off both ends so the motion
//    into and out of a position is not averaged in).
// 2. Gyro bias: the mean rate over all static samples ("static" mode needs one segment).
// 3. "six-position" mode: segments are grouped by the direction of gravity (within
//    orientation_merge_rad), each group's mean specific force is one orientation, and the
//    accelerometer bias and scale come from solve_accel_calibration (6+ orientations, every
//    axis once up and once down). The gyro's scale cannot be seen at rest: it stays 1.
#include <string>
#include <vector>

#include "core/common/samples.hpp"
#include "core/imu/accel_calibration.hpp"
#include "core/imu/imu_calibration.hpp"
#include "core/imu/still_detector.hpp"

namespace luxloc::calib {

enum class ImuCalibMode { static_only, six_position };

struct ImuCalibratorOptions {
  ImuCalibMode mode = ImuCalibMode::six_position;
  StillOptions still = loose_still();
  double min_segment_s = 2.0;             // shorter still runs are ignored
  double orientation_merge_rad = 0.5;     // ~30 deg: segments closer are one orientation
  double gravity = 9.80665;
  // An uncalibrated IMU may read g off by several percent and carry a large gyro bias: the
  // detector then only looks at the spread of the readings.
  static StillOptions loose_still() {
    StillOptions s;
    s.window_s = 0.5;
    s.gyro_mean_max_rps = 0.5;
    s.acc_norm_tolerance_mps2 = 2.0;
    return s;
  }
};

struct StaticSegment {
  TimeNs t0 = 0, t1 = 0;
  std::size_t samples = 0;
  Eigen::Vector3d mean_acc = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_gyro = Eigen::Vector3d::Zero();
  int orientation = -1;  // index into ImuCalibrationResult::orientations (six-position)
};

struct ImuCalibrationResult {
  ImuCalibration calibration;
  std::vector<StaticSegment> segments;
  std::vector<Eigen::Vector3d> orientations;  // mean specific force per orientation
  AccelCalibrationResult accel;               // six-position only
  double static_seconds = 0.0;
  ImuCalibrationInfo info() const;
};

// Static segments of a log (samples in time order).
std::vector<StaticSegment> find_static_segments(const std::vector<ImuSample>& samples, const StillOptions& still,
                                                double min_segment_s);

// Throws std::invalid_argument with a message for the user when the log does not allow the
// calibration (no static segment; fewer than 6 orientations; axes never up or down).
ImuCalibrationResult calibrate_imu(const std::vector<ImuSample>& samples, const ImuCalibratorOptions& options);

}  // namespace luxloc::calib
