#include <catch2/catch.hpp>
#include <cstdio>

#include "calib/imu_calibrator.hpp"
#include "six_position_log.hpp"

using namespace luxloc;

TEST_CASE("calib imu: six-position log recovers accelerometer bias and scale and gyro bias within 1 %", "[imu]") {
  const test::ImuErrorModel truth;
  const std::vector<ImuSample> log = test::six_position_log(truth);
  const calib::ImuCalibrationResult r = calib::calibrate_imu(log, {});
  REQUIRE(r.segments.size() == 6);
  REQUIRE(r.orientations.size() == 6);
  for (const calib::StaticSegment& s : r.segments) CHECK(ns_to_seconds(s.t1 - s.t0) > 4.0);
  const ImuCalibration& c = r.calibration;
  std::printf("[imu] six-position: acc bias err %.5f %.5f %.5f m/s^2, scale err %.5f %.5f %.5f, gyro bias err %.6f "
              "%.6f %.6f rad/s, residual %.4f\n",
              c.acc_bias.x() - truth.acc_bias.x(), c.acc_bias.y() - truth.acc_bias.y(),
              c.acc_bias.z() - truth.acc_bias.z(), c.acc_scale.x() - truth.acc_scale.x(),
              c.acc_scale.y() - truth.acc_scale.y(), c.acc_scale.z() - truth.acc_scale.z(),
              c.gyro_bias.x() - truth.gyro_bias.x(), c.gyro_bias.y() - truth.gyro_bias.y(),
              c.gyro_bias.z() - truth.gyro_bias.z(), r.accel.residual_rms_mps2);
  for (int j = 0; j < 3; ++j) {
    CHECK(std::abs(c.acc_bias[j] - truth.acc_bias[j]) <= 0.01 * std::abs(truth.acc_bias[j]));
    CHECK(std::abs(c.acc_scale[j] - truth.acc_scale[j]) <= 0.01 * truth.acc_scale[j]);
    CHECK(std::abs(c.gyro_bias[j] - truth.gyro_bias[j]) <= 0.01 * std::abs(truth.gyro_bias[j]));
  }
  CHECK(r.info().method == "six-position");
  // The corrected readings at rest have magnitude g in every orientation.
  for (const Eigen::Vector3d& m : r.orientations)
    CHECK((m - c.acc_bias).cwiseQuotient(c.acc_scale).norm() == Approx(9.80665).epsilon(1e-3));
}

TEST_CASE("calib imu: static mode needs one still segment, six-position names what is missing", "[imu]") {
  const std::vector<ImuSample> three = test::six_position_log({}, 3);
  calib::ImuCalibratorOptions o;
  o.mode = calib::ImuCalibMode::static_only;
  const calib::ImuCalibrationResult r = calib::calibrate_imu(three, o);
  CHECK(r.segments.size() == 3);
  CHECK(r.calibration.acc_scale == Eigen::Vector3d::Ones());
  CHECK((r.calibration.gyro_bias - test::ImuErrorModel{}.gyro_bias).norm() < 3e-4);
  o.mode = calib::ImuCalibMode::six_position;
  try {
    calib::calibrate_imu(three, o);
    FAIL("expected an error");
  } catch (const std::invalid_argument& e) {
    CHECK_THAT(e.what(), Catch::Contains("found 3 static orientation(s) (+z -z +x up)"));
  }
  // Only motion: no static segment.
  std::vector<ImuSample> moving = test::six_position_log({}, 2);
  moving.erase(moving.begin(), moving.begin() + 500);  // drop the first rest
  moving.resize(200);                                   // keep the turn only
  CHECK_THROWS_WITH(calib::calibrate_imu(moving, o), Catch::Contains("no static segment"));
}
