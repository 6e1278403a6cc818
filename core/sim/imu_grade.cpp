#include "core/sim/imu_grade.hpp"

#include <numbers>
#include <stdexcept>

namespace luxloc::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

std::vector<std::string> imu_grade_names() { return {"default", "ideal", "tactical", "consumer", "poor"}; }

ImuNoise imu_grade(const std::string& name) {
  ImuNoise n;  // "default": the historic sim IMU (0.3 deg/s bias, no walk, no scale error)
  if (name == "default") return n;
  if (name == "ideal") return ImuNoise::none();
  if (name == "tactical") {
    // A fibre-optic / high-end MEMS unit: biases of ~0.01 deg/s, scale within 100 ppm.
    n.acc_noise_mps2 = 0.005;
    n.gyro_noise_rps = 0.001;
    n.mag_noise_ut = 0.1;
    n.acc_bias_sigma_mps2 = 0.005;
    n.gyro_bias_sigma_rps = 0.01 * kDeg;
    n.gyro_bias_rw_rps_sqrt_s = 0.0005 * kDeg;
    n.gyro_scale_sigma = n.acc_scale_sigma = 1e-4;
    return n;
  }
  if (name == "consumer") {
    // A phone / MPU-class MEMS part: turn-on gyro bias up to 1 deg/s per axis (sigma 0.5,
    // clamped at 1), a bias that wanders by ~0.05 deg/s over 90 s (0.005 deg/s/sqrt(s)),
    // scale errors of 0.5 % (gyro) and 0.3 % (accelerometer).
    n.gyro_bias_sigma_rps = 0.5 * kDeg;
    n.gyro_bias_max_rps = 1.0 * kDeg;
    n.gyro_bias_rw_rps_sqrt_s = 0.005 * kDeg;
    n.gyro_scale_sigma = 0.005;
    n.acc_scale_sigma = 0.003;
    return n;
  }
  if (name == "poor") {
    // An uncalibrated low-cost part: bias at the 1 deg/s limit on most axes (sigma 1,
    // clamped at 1), a fast walk (0.02 deg/s/sqrt(s): ~0.2 deg/s in 90 s), twice the noise,
    // 2 % / 1 % scale errors and a 0.15 m/s^2 accelerometer bias.
    n.acc_noise_mps2 = 0.04;
    n.gyro_noise_rps = 0.01;
    n.mag_noise_ut = 0.6;
    n.acc_bias_sigma_mps2 = 0.15;
    n.gyro_bias_sigma_rps = 1.0 * kDeg;
    n.gyro_bias_max_rps = 1.0 * kDeg;
    n.gyro_bias_rw_rps_sqrt_s = 0.02 * kDeg;
    n.gyro_scale_sigma = 0.02;
    n.acc_scale_sigma = 0.01;
    return n;
  }
  throw std::invalid_argument("unknown IMU grade '" + name + "' (default, ideal, tactical, consumer, poor)");
}

}  // namespace luxloc::sim
