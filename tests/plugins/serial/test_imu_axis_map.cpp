#include <catch2/catch.hpp>

#include "plugins/serial/imu_axis_map.hpp"

using namespace luxloc;

TEST_CASE("IMU axis map: signed permutations that are rotations", "[imu]") {
  CHECK(ImuAxisMap::parse("+x+y+z").identity());
  const ImuAxisMap m = ImuAxisMap::parse("+y-x+z");
  CHECK((m.apply(Eigen::Vector3d(1, 2, 3)) - Eigen::Vector3d(2, -1, 3)).norm() == 0.0);
  ImuSample s;
  s.acc_inB = {1, 0, 0};
  s.gyro_inB = {0, 1, 0};
  s.mag_inB = {0, 0, 1};
  s.has_mag = true;
  const ImuSample o = ImuAxisMap::parse("-x-y+z").apply(s);
  CHECK(o.acc_inB.x() == -1.0);
  CHECK(o.gyro_inB.y() == -1.0);
  CHECK(o.mag_inB.z() == 1.0);
  CHECK_THROWS_WITH(ImuAxisMap::parse("+x+x+z"), Catch::Contains("not a rotation"));
  CHECK_THROWS_WITH(ImuAxisMap::parse("-x+y+z"), Catch::Contains("not a rotation"));  // mirror
  CHECK_THROWS_AS(ImuAxisMap::parse("xyz"), std::invalid_argument);
  CHECK_THROWS_AS(ImuAxisMap::parse("+x+y+w"), std::invalid_argument);
}
