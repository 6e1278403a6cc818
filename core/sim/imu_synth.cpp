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
  ImuSample m = ideal_imu(s, noise.mag_field_inW);
  m.acc_inB += biases.acc + normal3(rng, noise.acc_noise_mps2);
  m.gyro_inB += biases.gyro + normal3(rng, noise.gyro_noise_rps);
  m.mag_inB += normal3(rng, noise.mag_noise_ut);
  return m;
}

}  // namespace luxloc::sim
