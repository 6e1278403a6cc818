// Physical plausibility at the edge: what each sensor can measure (core/common/sensor_limits).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/common/drop_counts.hpp"
#include "core/common/sensor_limits.hpp"

using namespace luxloc;

namespace {

ImuSample at_rest() {
  ImuSample s;
  s.acc_inB = {0.1, -0.2, 9.81};
  s.gyro_inB = {0.01, 0.0, -0.02};
  s.mag_inB = {20.0, 5.0, -40.0};
  s.has_mag = true;
  return s;
}

}  // namespace

TEST_CASE("sensor limits: a sample at rest passes, each impossible IMU axis is named", "[limits]") {
  const SensorLimits l;
  CHECK_FALSE(check_plausible(at_rest(), l));
  const char* names[9] = {"ax", "ay", "az", "gx", "gy", "gz", "mx", "my", "mz"};
  for (int axis = 0; axis < 9; ++axis)
    for (double v : {1e30, -1e30, std::numeric_limits<double>::infinity(), std::nan("")}) {
      ImuSample s = at_rest();
      Eigen::Vector3d& vec = axis < 3 ? s.acc_inB : axis < 6 ? s.gyro_inB : s.mag_inB;
      vec[axis % 3] = v;
      const auto bad = check_plausible(s, l);
      INFO("axis " << names[axis] << " = " << v);
      REQUIRE(bad);
      CHECK(bad->field == names[axis]);
    }
}

TEST_CASE("sensor limits: the defaults are 16 g, 2000 deg/s, 1000 uT, per axis", "[limits]") {
  const SensorLimits l;
  ImuSample s = at_rest();
  s.acc_inB.x() = 15.9 * 9.80665;
  CHECK_FALSE(check_plausible(s, l));
  s.acc_inB = Eigen::Vector3d::Constant(15.9 * 9.80665);  // |a| above 16 g, each axis within
  CHECK_FALSE(check_plausible(s, l));
  s.acc_inB.z() = 16.1 * 9.80665;
  CHECK(check_plausible(s, l)->field == "az");
  s = at_rest();
  s.gyro_inB.y() = 1990.0 * 3.141592653589793 / 180.0;
  CHECK_FALSE(check_plausible(s, l));
  s.gyro_inB.y() = -2010.0 * 3.141592653589793 / 180.0;
  CHECK_THAT(check_plausible(s, l)->what, Catch::Contains("beyond the sensor's range"));
  s = at_rest();
  s.mag_inB.x() = 1001.0;
  CHECK(check_plausible(s, l)->field == "mx");
  s.has_mag = false;  // no magnetometer reading: its (zeroed or stale) values are not checked
  CHECK_FALSE(check_plausible(s, l));
  SensorLimits small;
  small.acc_max_mps2 = 2.0 * 9.80665;  // a 2 g part
  s = at_rest();
  s.acc_inB.x() = 3.0 * 9.80665;
  CHECK(check_plausible(s, small)->field == "ax");
  CHECK_FALSE(check_plausible(s, l));
}

TEST_CASE("sensor limits: UWB range 0-200 m, AOA finite when given, fixes and odometry bounded", "[limits]") {
  const SensorLimits l;
  UwbSample u;
  u.range_m = 12.5;
  CHECK_FALSE(check_plausible(u, l));  // no AOA (NaN) is fine
  u.aoa_rad = 1.2;
  CHECK_FALSE(check_plausible(u, l));
  u.aoa_rad = std::numeric_limits<double>::infinity();
  CHECK(check_plausible(u, l)->field == "aoa_rad");
  u.aoa_rad = 0.3;
  for (double r : {-0.01, 200.5, 1e30, std::nan("")}) {
    u.range_m = r;
    INFO("range " << r);
    CHECK(check_plausible(u, l)->field == "range_m");
  }
  FixSample f;
  f.p_inW = {3.0, 4.0};
  CHECK_FALSE(check_plausible(f, l));
  f.p_inW.y() = 1e30;
  CHECK(check_plausible(f, l)->field == "y");
  OdomSample o;
  o.dist_m = 0.3;
  CHECK_FALSE(check_plausible(o, l));
  o.dist_m = -1e30;
  CHECK(check_plausible(o, l)->field == "dist_m");
  CHECK_FALSE(check_plausible(SensorData(FrameSample{}), l));
}

TEST_CASE("sensor limits: admit_plausible counts a refused sample as out of range", "[limits]") {
  DropCounts drops;
  ImuSample s = at_rest();
  CHECK(admit_plausible(s, {}, drops, "serial-imu:/dev/ttyX"));
  s.gyro_inB.x() = 1e30;
  CHECK_FALSE(admit_plausible(s, {}, drops, "serial-imu:/dev/ttyX"));
  CHECK(drops.count(drop_reason::kOutOfRange) == 1);
  CHECK_THAT(drops.snapshot().at(drop_reason::kOutOfRange).first_message,
             Catch::Contains("serial-imu:/dev/ttyX: field 'gx'"));
}
