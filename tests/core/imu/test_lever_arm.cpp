// LeverArm (issue 12 part 1): where a walker holds the device, from the circle it draws when
// the walker turns round on the spot.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/imu/lever_arm.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/walk_trajectory.hpp"

using namespace luxloc;

namespace {

// The walk scenario's walker stopping at 30 s and turning round on the spot (180 deg in
// `turn_s`), the device held at `lever`; the standing stretch fed at 100 Hz with the
// consumer grade's accelerometer bias (0.05 m/s^2) and noise (0.02 m/s^2), and the gyro's
// rate noise (0.005 rad/s).
LeverArm learn(const Eigen::Vector2d& lever, double turn_s) {
  const sim::Scenario sc = sim::make_scenario("walk");
  sim::WalkOptions o = *sc.walk;
  o.walking = {{2.0, 30.0}, {35.0, std::numeric_limits<double>::infinity()}};
  o.turns = {{32.5 - 0.5 * turn_s, turn_s, true}};
  o.lever_arm_m = lever;
  const sim::WalkTrajectory tr(o);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> acc_noise(0.0, 0.02), gyro_noise(0.0, 0.005);
  LeverArm arm;
  for (double t = 30.0; t < 35.0; t += 0.01) {
    const sim::BodyState b = tr.state(t);
    const Eigen::Vector2d a = b.a_BinW.head<2>() + Eigen::Vector2d(0.05 + acc_noise(rng), -0.05 + acc_noise(rng));
    arm.update_standing(seconds_to_ns(t), b.yaw, (b.R_BtoW * b.omega_inB).z() + gyro_noise(rng), a);
  }
  arm.interrupt();  // walking again
  return arm;
}

}  // namespace

TEST_CASE("LeverArm: a turn round on the spot gives where the device is held", "[imu][lever]") {
  for (const Eigen::Vector2d& lever : {Eigen::Vector2d(0.3, 0.0), Eigen::Vector2d(0.15, -0.2), Eigen::Vector2d(0.4, 0.2)}) {
    for (double turn_s : {1.0, 2.0}) {
      INFO("lever " << lever.transpose() << ", turn in " << turn_s << " s");
      const LeverArm arm = learn(lever, turn_s);
      REQUIRE(arm.lever());
      CHECK(arm.turns_used() == 1);
      CHECK((*arm.lever() - lever).norm() < 0.03);  // the 20 ms rate smoothing lags psi'' (2.1 cm at 0.45 m, 1 s)
      // The device's place in the world turns with the heading.
      const Eigen::Vector2d east = arm.offset_inW(0.0), north = arm.offset_inW(0.5 * std::numbers::pi);
      CHECK((north - Eigen::Vector2d(-east.y(), east.x())).norm() < 1e-12);
    }
  }
}

TEST_CASE("LeverArm: a device on the axis, too small a turn, bad samples: nothing learnt", "[imu][lever]") {
  // On the axis the turn's acceleration is the noise: the fit explains none of it.
  const LeverArm axis = learn(Eigen::Vector2d::Zero(), 1.5);
  CHECK_FALSE(axis.lever());
  CHECK(axis.turns_refused() == 1);
  // A quarter of a turn over 4 s hardly excites anything.
  LeverArm slow;
  for (double t = 0.0; t < 4.0; t += 0.01) slow.update_standing(seconds_to_ns(t), 0.4 * t, 0.4, {0.0, 0.0});
  slow.interrupt();
  CHECK_FALSE(slow.lever());
  CHECK(slow.turns_used() + slow.turns_refused() == 0);
  // NaN samples are skipped; nothing before a turn.
  LeverArm nan;
  nan.update_standing(0, std::numeric_limits<double>::quiet_NaN(), 2.0, {1.0, 0.0});
  CHECK_FALSE(nan.turning());
  CHECK(nan.offset_inW(1.0).isZero());
}
