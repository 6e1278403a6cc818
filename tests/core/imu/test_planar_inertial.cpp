#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <numbers>

#include "core/imu/planar_inertial.hpp"

using namespace luxloc;

TEST_CASE("Planar inertial integration: constant acceleration, heading change, zero velocity at rest", "[imu]") {
  PlanarInertialIntegrator pi;
  // Device level, yawed 90 deg (body x = world north), accelerating 1 m/s^2 along body x.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  ImuSample s;
  s.acc_inB = {1.0, 0.0, 9.80665};
  for (int k = 0; k <= 200; ++k) {
    s.t = TimeNs{k} * 10'000'000;
    s.gyro_inB = {0, 0, 0.3};  // moving: not still
    pi.update(s, R);
  }
  PlanarIncrement inc = pi.take();
  CHECK(ns_to_seconds(inc.t1 - inc.t0) == Approx(2.0));
  CHECK(inc.dp_inW.x() == Approx(0.0).margin(1e-9));
  CHECK(inc.dp_inW.y() == Approx(0.5 * 1.0 * 4.0).epsilon(1e-6));  // x = a t^2 / 2
  CHECK(inc.v_inW.y() == Approx(2.0).epsilon(1e-6));
  CHECK_FALSE(inc.at_rest);
  // Standing still: the velocity is reset, the displacement stops growing.
  s.acc_inB = {0.0, 0.0, 9.80665};
  s.gyro_inB.setZero();
  for (int k = 201; k <= 400; ++k) {
    s.t = TimeNs{k} * 10'000'000;
    pi.update(s, R);
  }
  inc = pi.take();
  CHECK(inc.at_rest);
  CHECK(inc.v_inW.norm() == 0.0);
  CHECK(inc.dp_inW.y() < 2.0 * 0.5);  // at most the 0.4 s detector window at 2 m/s
  // Heading changes are summed through the wrap.
  PlanarInertialIntegrator turn;
  for (int k = 0; k <= 100; ++k) {
    s.t = TimeNs{k} * 10'000'000;
    turn.update(s, Eigen::AngleAxisd(3.0 + 0.01 * k, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  }
  CHECK(turn.take().dyaw_rad == Approx(1.0).epsilon(1e-9));
}
