#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/filter/fast_rng.hpp"
#include "core/imu/mahony_filter.hpp"

using namespace luxloc;

namespace {

// IMU reading of a static device with attitude R_BtoW in the ENU field (0, 22, -42) uT.
ImuSample static_sample(const Eigen::Matrix3d& R_BtoW, TimeNs t, const Eigen::Vector3d& gyro_bias) {
  ImuSample s;
  s.t = t;
  s.acc_inB = R_BtoW.transpose() * Eigen::Vector3d(0, 0, 9.80665);
  s.gyro_inB = gyro_bias;
  s.mag_inB = R_BtoW.transpose() * Eigen::Vector3d(0, 22, -42);
  s.has_mag = true;
  return s;
}

Eigen::Matrix3d ypr(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

TEST_CASE("Mahony aligns roll, pitch and yaw at rest (SEEDS C.1)", "[imu]") {
  const double yaw = 2.0, pitch = -0.2, roll = 0.3;
  MahonyFilter f;
  f.update(static_sample(ypr(yaw, pitch, roll), 0, Eigen::Vector3d::Zero()));
  REQUIRE(f.initialized());
  CHECK(f.yaw() == Approx(yaw).margin(1e-9));
  CHECK(f.pitch() == Approx(pitch).margin(1e-9));
  CHECK(f.roll() == Approx(roll).margin(1e-9));
}

TEST_CASE("Mahony learns a gyro bias and holds the attitude (SEEDS C.3)", "[imu]") {
  const Eigen::Vector3d bias(0.01, -0.008, 0.012);  // ~0.6 deg/s
  const Eigen::Matrix3d R = ypr(0.5, 0.05, -0.1);
  MahonyOptions opt;
  opt.ki = 0.05;
  MahonyFilter f(opt);
  FastRng rng(1);
  for (int k = 0; k < 100 * 120; ++k) {
    ImuSample s = static_sample(R, TimeNs{k} * 10'000'000, bias);
    s.gyro_inB += 0.003 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    s.acc_inB += 0.02 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    f.update(s);
  }
  CHECK((f.gyro_bias() - bias).norm() < 0.002);
  CHECK(f.yaw() == Approx(0.5).margin(0.01));
  CHECK(f.roll() == Approx(-0.1).margin(0.005));
  CHECK(f.pitch() == Approx(0.05).margin(0.005));
}

TEST_CASE("Mahony follows a rotation and ignores non-finite samples", "[imu]") {
  MahonyFilter f;
  const double rate = 0.5;  // rad/s about world z
  for (int k = 0; k <= 200; ++k) {
    const double t = k * 0.01;
    ImuSample s = static_sample(ypr(rate * t, 0, 0), TimeNs{k} * 10'000'000, Eigen::Vector3d::Zero());
    s.gyro_inB = Eigen::Vector3d(0, 0, rate);
    f.update(s);
    if (k == 100) {
      ImuSample bad = s;
      bad.t += 1;
      bad.gyro_inB.x() = NAN;
      f.update(bad);
    }
  }
  CHECK(f.rejected_samples() == 1);
  CHECK(f.yaw() == Approx(1.0).margin(0.01));
}
