#pragma once
// Synthetic IMU (accelerometer, gyroscope, magnetometer) in the body frame (FLU) from the
// exact trajectory derivatives (docs/SIMULATOR.md "IMU"):
//   acc  = R_BtoW^T (a_W + [0, 0, g]) + b_a + n_a       (specific force: +g on z at rest)
//   gyro = omega_inB + b_g + n_g
//   mag  = R_BtoW^T m_W + n_m
// with constant per-run biases and white noise per sample.
#include <Eigen/Core>
#include <random>

#include "core/common/samples.hpp"
#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

inline constexpr double kGravity = 9.81;  // m/s^2, SPEC: "about +9.81 on z at rest"

// Values of a consumer MEMS IMU sampled at 100 Hz (1 sigma, per sample / per run).
struct ImuNoise {
  double acc_noise_mps2 = 0.02;         // white noise per sample (~200 ug/sqrt(Hz) at 100 Hz)
  double gyro_noise_rps = 0.005;        // white noise per sample (~0.03 deg/s/sqrt(Hz))
  double mag_noise_ut = 0.3;            // white noise per sample
  double acc_bias_sigma_mps2 = 0.05;    // constant per-run bias, each axis ~ N(0, sigma)
  double gyro_bias_sigma_rps = 0.3 * 3.14159265358979323846 / 180.0;  // 0.3 deg/s
  Eigen::Vector3d mag_field_inW{0.0, 22.0, -42.0};  // Earth field, ENU, microtesla (mid-latitude)

  static ImuNoise none() {
    ImuNoise n;
    n.acc_noise_mps2 = n.gyro_noise_rps = n.mag_noise_ut = 0.0;
    n.acc_bias_sigma_mps2 = n.gyro_bias_sigma_rps = 0.0;
    return n;
  }
};

struct ImuBiases {
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
};

// Draws the per-run biases (each axis normal with the ImuNoise sigmas).
ImuBiases draw_imu_biases(const ImuNoise& noise, std::mt19937_64& rng);

// Noise-free, bias-free readings at the state's time.
ImuSample ideal_imu(const BodyState& s, const Eigen::Vector3d& mag_field_inW = ImuNoise{}.mag_field_inW);

// One measured sample: ideal readings plus biases plus white noise drawn from rng.
ImuSample synthesize_imu(const BodyState& s, const ImuNoise& noise, const ImuBiases& biases,
                         std::mt19937_64& rng);

}  // namespace luxloc::sim
