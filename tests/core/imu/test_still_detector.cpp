#include <catch2/catch.hpp>

#include "core/filter/fast_rng.hpp"
#include "core/imu/still_detector.hpp"

using namespace luxloc;

namespace {
ImuSample sample(TimeNs t, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc) {
  ImuSample s;
  s.t = t;
  s.gyro_inB = gyro;
  s.acc_inB = acc;
  return s;
}
}  // namespace

TEST_CASE("StillDetector: quiet readings are still, the mean rate is the bias, motion ends it", "[imu]") {
  StillDetector d;
  FastRng rng(3);
  const Eigen::Vector3d bias(0.004, -0.006, 0.002);
  TimeNs t = 0;
  bool still = false;
  for (int k = 0; k < 300; ++k, t += 10'000'000) {
    const Eigen::Vector3d n(rng.normal(), rng.normal(), rng.normal());
    still = d.update(sample(t, bias + 0.005 * n, Eigen::Vector3d(0, 0, 9.80665) + 0.02 * n));
    if (k < 38) CHECK_FALSE(still);  // the window (0.4 s) is not full yet
  }
  REQUIRE(still);
  CHECK(d.still_duration_s() == Approx(2.6).margin(0.05));
  CHECK(d.still_samples() >= 260);
  // 260+ samples of 0.005 rad/s noise: the mean is within ~4 sigma of the bias.
  CHECK((d.still_mean_gyro() - bias).norm() < 0.0015);
  // A turn: rate well above the thresholds.
  for (int k = 0; k < 10; ++k, t += 10'000'000)
    still = d.update(sample(t, Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(0, 0, 9.80665)));
  CHECK_FALSE(still);
  CHECK(d.still_duration_s() == 0.0);
  CHECK(d.still_samples() == 0);
}

TEST_CASE("StillDetector: shaking (acc spread) and free fall are not still, NaN is ignored", "[imu]") {
  StillDetector d;
  TimeNs t = 0;
  for (int k = 0; k < 100; ++k, t += 10'000'000)
    d.update(sample(t, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.80665 + ((k % 2) ? 0.5 : -0.5))));
  CHECK_FALSE(d.still());
  StillDetector fall;
  for (int k = 0; k < 100; ++k, t += 10'000'000) fall.update(sample(t, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  CHECK_FALSE(fall.still());
  StillDetector nan;
  for (int k = 0; k < 100; ++k, t += 10'000'000) nan.update(sample(t, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.8)));
  REQUIRE(nan.still());
  nan.update(sample(t, Eigen::Vector3d::Constant(NAN), Eigen::Vector3d(0, 0, 9.8)));
  CHECK(nan.still());
  CHECK(nan.mean_gyro().allFinite());
}
