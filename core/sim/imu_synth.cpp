#include "core/sim/imu_synth.hpp"

namespace luxloc::sim {
namespace {

Eigen::Vector3d normal3(std::mt19937_64& rng, double sigma) {
  if (sigma <= 0.0) return Eigen::Vector3d::Zero();
  std::normal_distribution<double> n(0.0, sigma);
  const double x = n(rng), y = n(rng), z = n(rng);  // sequenced: deterministic order
  return {x, y, z};
}

}  // namespace

ImuBiases draw_imu_biases(const ImuNoise& noise, std::mt19937_64& rng) {
  ImuBiases b;
  b.acc = normal3(rng, noise.acc_bias_sigma_mps2);
  b.gyro = normal3(rng, noise.gyro_bias_sigma_rps);
  if (noise.gyro_bias_max_rps > 0.0)
    b.gyro = b.gyro.cwiseMax(-noise.gyro_bias_max_rps).cwiseMin(noise.gyro_bias_max_rps);
  if (noise.gyro_bias_fixed) b.gyro = noise.gyro_bias_fixed_rps;
  return b;
}

ImuBiases draw_imu_biases(const ImuNoise& noise, std::mt19937_64& rng, std::mt19937_64& scale_rng) {
  ImuBiases b = draw_imu_biases(noise, rng);
  b.gyro_scale += normal3(scale_rng, noise.gyro_scale_sigma);
  b.acc_scale += normal3(scale_rng, noise.acc_scale_sigma);
  return b;
}

ImuSample ideal_imu(const BodyState& s, const Eigen::Vector3d& mag_field_inW) {
  ImuSample m;
  m.t = seconds_to_ns(s.t);
  m.acc_inB = s.R_BtoW.transpose() * (s.a_BinW + Eigen::Vector3d(0.0, 0.0, kGravity));
  m.gyro_inB = s.omega_inB;
  m.mag_inB = s.R_BtoW.transpose() * mag_field_inW;
  m.has_mag = true;
  return m;
}

ImuSample synthesize_imu(const BodyState& s, const ImuNoise& noise, const ImuBiases& biases,
                         std::mt19937_64& rng) {
  return synthesize_imu(s, noise, biases, rng, noise.mag_field_inW);
}

ImuSample synthesize_imu(const BodyState& s, const ImuNoise& noise, const ImuBiases& biases, std::mt19937_64& rng,
                         const Eigen::Vector3d& mag_field_inW) {
  ImuSample m = ideal_imu(s, mag_field_inW);
  // x * 1.0 is exact: without scale errors the readings are the historic ones bit for bit.
  m.acc_inB = m.acc_inB.cwiseProduct(biases.acc_scale);
  m.gyro_inB = m.gyro_inB.cwiseProduct(biases.gyro_scale);
  m.acc_inB += biases.acc + normal3(rng, noise.acc_noise_mps2);
  m.gyro_inB += biases.gyro + normal3(rng, noise.gyro_noise_rps);
  m.mag_inB += normal3(rng, noise.mag_noise_ut);
  return m;
}

}  // namespace luxloc::sim
