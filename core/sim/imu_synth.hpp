#pragma once
// Synthetic IMU (accelerometer, gyroscope, magnetometer) in the body frame (FLU) from the
// exact trajectory derivatives (docs/SIMULATOR.md "IMU"):
//   acc  = S_a R_BtoW^T (a_W + [0, 0, g]) + b_a + n_a    (specific force: +g on z at rest)
//   gyro = S_g omega_inB + b_g(t) + n_g
//   mag  = R_BtoW^T m_W(p, t) + n_m
// with per-run biases and scale factors S = diag(1 + s), a gyro bias that may walk
// (b_g(t_k+1) = b_g(t_k) + sigma_rw sqrt(dt) n), and white noise per sample. The defaults
// (no scale error, no walk, a clean field) are the simulator's historic IMU: the grades of
// imu_grade.hpp add the rest.
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
  // Zero by default, so that the historic sessions stay bit-identical (no extra draws).
  double gyro_bias_max_rps = 0.0;        // > 0: each drawn gyro bias axis clamped to +-this
  double gyro_bias_rw_rps_sqrt_s = 0.0;  // gyro bias random walk (rad/s per sqrt(s))
  double gyro_scale_sigma = 0.0;         // per-axis gyro scale error ~ N(0, sigma) (fraction)
  double acc_scale_sigma = 0.0;          // per-axis accelerometer scale error ~ N(0, sigma)
  bool gyro_bias_fixed = false;          // true: gyro_bias_fixed_rps instead of a draw
  Eigen::Vector3d gyro_bias_fixed_rps = Eigen::Vector3d::Zero();

  static ImuNoise none() {
    ImuNoise n;
    n.acc_noise_mps2 = n.gyro_noise_rps = n.mag_noise_ut = 0.0;
    n.acc_bias_sigma_mps2 = n.gyro_bias_sigma_rps = 0.0;
    return n;
  }
};

struct ImuBiases {
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  // at t = 0 (it may walk from there)
  Eigen::Vector3d acc_scale = Eigen::Vector3d::Ones();   // 1 + scale error, per axis
  Eigen::Vector3d gyro_scale = Eigen::Vector3d::Ones();
};

// Draws the per-run biases (each axis normal with the ImuNoise sigmas, gyro clamped to
// gyro_bias_max_rps when set, or the fixed gyro bias) from rng, and the scale errors from
// scale_rng (a stream of its own: historic sessions draw nothing from it).
ImuBiases draw_imu_biases(const ImuNoise& noise, std::mt19937_64& rng);
ImuBiases draw_imu_biases(const ImuNoise& noise, std::mt19937_64& rng, std::mt19937_64& scale_rng);

// Noise-free, bias-free readings at the state's time.
ImuSample ideal_imu(const BodyState& s, const Eigen::Vector3d& mag_field_inW = ImuNoise{}.mag_field_inW);

// One measured sample: ideal readings plus biases plus white noise drawn from rng.
ImuSample synthesize_imu(const BodyState& s, const ImuNoise& noise, const ImuBiases& biases,
                         std::mt19937_64& rng);
// The same in a field that varies along the path (steel, magnets: mag_disturbance.hpp).
ImuSample synthesize_imu(const BodyState& s, const ImuNoise& noise, const ImuBiases& biases, std::mt19937_64& rng,
                         const Eigen::Vector3d& mag_field_inW);

}  // namespace luxloc::sim
