#pragma once
// A synthetic six-position calibration log with a known IMU error model, for the
// calibration tests: the IMU rests 5 s in each of six orientations (each a few degrees off
// the ideal, as on a real table), turning between them for 2 s.
#include <Eigen/Geometry>
#include <vector>

#include "core/common/samples.hpp"
#include "core/filter/fast_rng.hpp"

namespace luxloc::test {

struct ImuErrorModel {
  Eigen::Vector3d acc_bias{0.15, -0.22, 0.31};
  Eigen::Vector3d acc_scale{1.012, 0.985, 1.021};
  Eigen::Vector3d gyro_bias{0.021, -0.015, 0.011};
  double acc_noise = 0.02, gyro_noise = 0.003;
};

inline std::vector<ImuSample> six_position_log(const ImuErrorModel& m, int n_orientations = 6, std::uint64_t seed = 5) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  const double g = 9.80665, pi = 3.14159265358979323846;
  // Body-to-world attitudes putting +z, -z, +x, -x, +y, -y up, tilted a little.
  const Eigen::Quaterniond ideal[6] = {
      Eigen::Quaterniond::Identity(),
      Eigen::Quaterniond(AngleAxisd(pi, Vector3d::UnitX())),
      Eigen::Quaterniond(AngleAxisd(-pi / 2, Vector3d::UnitY())),
      Eigen::Quaterniond(AngleAxisd(pi / 2, Vector3d::UnitY())),
      Eigen::Quaterniond(AngleAxisd(pi / 2, Vector3d::UnitX())),
      Eigen::Quaterniond(AngleAxisd(-pi / 2, Vector3d::UnitX())),
  };
  FastRng rng(seed);
  std::vector<ImuSample> out;
  TimeNs t = 0;
  const TimeNs dt = 10'000'000;
  auto emit = [&](const Eigen::Quaterniond& q, const Vector3d& rate_inB) {
    ImuSample s;
    s.t = t;
    const Vector3d f_inB = q.conjugate() * Vector3d(0, 0, g);
    s.acc_inB = m.acc_scale.cwiseProduct(f_inB) + m.acc_bias +
                m.acc_noise * Vector3d(rng.normal(), rng.normal(), rng.normal());
    s.gyro_inB = rate_inB + m.gyro_bias + m.gyro_noise * Vector3d(rng.normal(), rng.normal(), rng.normal());
    out.push_back(s);
    t += dt;
  };
  Eigen::Quaterniond prev;
  for (int i = 0; i < n_orientations; ++i) {
    const Eigen::Quaterniond q =
        ideal[i % 6] * Eigen::Quaterniond(AngleAxisd(0.05, Vector3d(0.3 * i, 1.0, -0.5 * i).normalized()));
    if (i > 0) {
      // Turn from prev to q in 2 s at a constant body rate.
      const Eigen::AngleAxisd d(prev.conjugate() * q);
      const Vector3d rate = d.axis() * d.angle() / 2.0;
      for (int k = 0; k < 200; ++k)
        emit(prev * Eigen::Quaterniond(AngleAxisd(d.angle() * k / 200.0, d.axis())), rate);
    }
    for (int k = 0; k < 500; ++k) emit(q, Vector3d::Zero());
    prev = q;
  }
  return out;
}

}  // namespace luxloc::test
