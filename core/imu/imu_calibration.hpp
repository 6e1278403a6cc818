#pragma once
// IMU calibration model (SEEDS.md C.4): per axis, measured = scale * true + bias, for the
// gyroscope, the accelerometer and the magnetometer (hard iron as its bias), in the body
// frame. apply() inverts it: true = (measured - bias) / scale.
//
// File (`luxloc calib imu` writes it; `luxloc imu --imu-calib` and `luxloc run --imu-calib`
// read it): OpenCV FileStorage YAML with 3-element sequences
//   gyro_bias (rad/s), gyro_scale, acc_bias (m/s^2), acc_scale, mag_bias (uT), mag_scale.
// Every key is optional (absent: bias 0, scale 1) but the file must hold at least one; a
// key of the wrong shape, a non-finite value or a scale outside [0.5, 2] is an InputError
// naming the file and the key. Other keys (residuals, provenance) are ignored on reading.
#include <Eigen/Core>
#include <string>

#include "core/common/samples.hpp"

namespace luxloc {

struct ImuCalibration {
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_scale = Eigen::Vector3d::Ones();
  Eigen::Vector3d acc_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d acc_scale = Eigen::Vector3d::Ones();
  Eigen::Vector3d mag_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d mag_scale = Eigen::Vector3d::Ones();

  // The corrected sample (time and has_mag unchanged).
  ImuSample apply(const ImuSample& measured) const;
  bool is_identity() const;
};

// Extra lines written as YAML keys after the model (numbers only), e.g. residuals.
struct ImuCalibrationInfo {
  std::string method;               // "static", "six-position"
  double acc_residual_rms_mps2 = -1;  // < 0: not written
  int static_segments = 0;
  double static_seconds = 0.0;
};

// Throws InputError(path, 0, key, ...) as described above.
ImuCalibration load_imu_calibration(const std::string& path);
// Throws std::runtime_error when the file cannot be written.
void save_imu_calibration(const std::string& path, const ImuCalibration& calib, const ImuCalibrationInfo& info = {});

}  // namespace luxloc
