// The walking scenario's trajectory: exact derivatives, a human-like walk (speed, bounce,
// sway, cadence, stops) that stays in the room and passes under every LED.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/sim/scenario.hpp"
#include "core/sim/walk_trajectory.hpp"

using namespace luxloc::sim;

namespace {

Eigen::Vector3d log_so3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// Velocity, acceleration and body rate at t against central differences of the poses
// (body rate: R(t+h) = R(t) Exp(omega h) to first order); returns the state at t.
BodyState check_derivatives(const Trajectory& tr, double t) {
  const double h = 1e-4;
  const BodyState s = tr.state(t), a = tr.state(t - h), b = tr.state(t + h);
  INFO("t " << t);
  CHECK((s.v_BinW - (b.p_BinW - a.p_BinW) / (2 * h)).norm() < 1e-6);
  CHECK((s.a_BinW - (b.v_BinW - a.v_BinW) / (2 * h)).norm() < 1e-4);
  CHECK((s.omega_inB - (log_so3(a.R_BtoW.transpose() * b.R_BtoW) / (2 * h))).norm() < 1e-5);
  return s;
}

}  // namespace

TEST_CASE("Walk trajectory derivatives are consistent with its poses", "[sim]") {
  const Scenario sc = make_scenario("walk");
  const Trajectory& tr = *sc.trajectory;
  for (double t = 0.5; t < 90.0; t += 0.731) {
    const BodyState s = check_derivatives(tr, t);
    // Euler angles reproduce the rotation.
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(s.yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(s.pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(s.roll, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    CHECK((R - s.R_BtoW).norm() < 1e-12);
  }
}

TEST_CASE("The walk looks like a person walking through the whole room", "[sim]") {
  const Scenario sc = make_scenario("walk");
  const Trajectory& tr = *sc.trajectory;
  // Standing still for the first 2 s at (3, 1), facing east, device 1 m high.
  for (double t = 0.0; t <= 2.0; t += 0.1) {
    const BodyState s = tr.state(t);
    CHECK(s.v_BinW.norm() < 1e-9);
    CHECK(s.a_BinW.norm() < 1e-9);
    CHECK(s.omega_inB.norm() < 1e-9);
    CHECK((s.p_BinW - Eigen::Vector3d(3, 1, 1)).norm() < 1e-4);
    CHECK(std::abs(s.yaw) < 1e-3);
  }
  double max_speed = 0, min_z = 9, max_z = -9, max_tilt = 0, max_heading_err = 0;
  double sum_speed = 0;
  int n_walk = 0;
  std::vector<double> closest(sc.map.size(), 1e9);
  for (double t = 0.0; t < 90.0; t += 0.01) {
    const BodyState s = tr.state(t);
    CHECK(s.p_BinW.x() > 0.5);
    CHECK(s.p_BinW.x() < sc.room_x_m - 0.5);
    CHECK(s.p_BinW.y() > 0.5);
    CHECK(s.p_BinW.y() < sc.room_y_m - 0.5);
    const double speed = s.v_BinW.head<2>().norm();
    max_speed = std::max(max_speed, speed);
    max_tilt = std::max({max_tilt, std::abs(s.roll), std::abs(s.pitch)});
    if (t > 4.0 && t < 29.0) {  // steady walking
      sum_speed += speed;
      ++n_walk;
      min_z = std::min(min_z, s.p_BinW.z());
      max_z = std::max(max_z, s.p_BinW.z());
    }
    if (speed > 0.5) {  // yaw follows the walking direction (within the sway)
      const double dir = std::atan2(s.v_BinW.y(), s.v_BinW.x());
      max_heading_err = std::max(max_heading_err, std::abs(std::remainder(s.yaw - dir, 2 * std::numbers::pi)));
    }
    for (std::size_t i = 0; i < sc.map.size(); ++i)
      closest[i] = std::min(closest[i], (sc.map.leds()[i].p_inW.head<2>() - s.p_BinW.head<2>()).norm());
  }
  CHECK(max_speed < 1.6);
  CHECK(sum_speed / n_walk > 1.0);
  CHECK(sum_speed / n_walk < 1.4);
  CHECK(max_z - min_z == Approx(0.03).margin(0.003));  // 3 cm bounce
  CHECK(max_tilt > 2.0 * std::numbers::pi / 180);
  CHECK(max_tilt < 3.0 * std::numbers::pi / 180);
  CHECK(max_heading_err < 1.1 * std::numbers::pi / 180);  // only the 1 deg yaw sway
  for (std::size_t i = 0; i < closest.size(); ++i) {
    INFO("LED " << sc.map.leds()[i].id);
    CHECK(closest[i] < 0.35);  // passes (nearly) under every LED
  }
  // Two brief stops.
  for (double t : {31.5, 32.5, 61.5, 62.5}) CHECK(tr.state(t).v_BinW.norm() < 1e-9);
}

TEST_CASE("Heel strikes: cadence 1.8 Hz, at the lowest point of the bounce", "[sim]") {
  const Scenario sc = make_scenario("walk");
  const std::vector<double> steps = sc.trajectory->step_times(90.0);
  REQUIRE(steps.size() > 130);
  CHECK(steps.size() < 160);
  CHECK(steps.front() > 2.0);
  int steady = 0;
  for (std::size_t i = 1; i < steps.size(); ++i) {
    const double dt = steps[i] - steps[i - 1];
    CHECK(dt > 0.5);
    if (steps[i] > 4.0 && steps[i] < 29.0) {
      CHECK(dt == Approx(1.0 / 1.8).margin(1e-6));
      ++steady;
    }
  }
  CHECK(steady > 40);
  for (double t : steps) {
    if (t < 4.0 || t > 29.0) continue;
    const BodyState s = sc.trajectory->state(t);
    CHECK(s.v_BinW.z() == Approx(0.0).margin(1e-6));  // bottom of the bounce
    CHECK(s.a_BinW.z() > 1.5);                          // vertical acceleration peaks
  }
  // None while standing.
  for (double t : steps) CHECK(!(t > 31.0 && t < 33.0));
}

TEST_CASE("A drifting pace and a turn round on the spot: exact derivatives, the walk goes back", "[sim][pace]") {
  const Scenario sc = make_scenario("walk");
  REQUIRE(sc.walk);
  WalkOptions o = *sc.walk;
  o.walking = {{2.0, 30.0}, {35.0, std::numeric_limits<double>::infinity()}};
  o.turns = {{31.5, 1.5, true}};
  o.gait.pace_waves = {{0.12, 30.0, 0.0}, {0.08, 100.0, 1.0}};
  o.gait.pace_horizon_s = 100.0;
  const WalkTrajectory tr(o);
  REQUIRE(tr.gait().drifts());
  for (double t = 0.5; t < 90.0; t += 0.613) check_derivatives(tr, t);
  // Standing through the turn: the position holds, the yaw turns by 180 deg (left: + pi).
  const BodyState before = tr.state(31.0), after = tr.state(33.5);
  CHECK((after.p_BinW - before.p_BinW).norm() < 1e-9);
  CHECK(std::remainder(after.yaw - before.yaw, 2 * std::numbers::pi) == Approx(std::numbers::pi).margin(0.05));
  CHECK(tr.state(32.25).omega_inB.z() > 1.5);  // turning at ~2 rad/s mid-turn
  // Walking again: back the way it came, facing where it goes.
  const BodyState in = tr.state(29.5), out = tr.state(35.5);  // near the turn, on either side
  CHECK(in.v_BinW.head<2>().normalized().dot(out.v_BinW.head<2>().normalized()) < -0.9);
  for (double t : {10.0, 25.0, 40.0, 60.0}) {
    const BodyState s = tr.state(t);
    const double dir = std::atan2(s.v_BinW.y(), s.v_BinW.x());
    CHECK(std::abs(std::remainder(s.yaw - dir, 2 * std::numbers::pi)) < 2.0 * std::numbers::pi / 180);
  }
  // The steps come at the drifting cadence: 1.8 Hz x sqrt(q) at each strike.
  const std::vector<double> strikes = tr.step_times(90.0);
  int checked = 0;
  for (std::size_t i = 1; i < strikes.size(); ++i) {
    if (tr.gait().envelope(strikes[i - 1]).v < 1.0 || tr.gait().envelope(strikes[i]).v < 1.0) continue;
    const double G = tr.gait().walked_time(0.5 * (strikes[i - 1] + strikes[i])).v;
    const double q = 1.0 + 0.12 * std::sin(2 * std::numbers::pi * G / 30.0) + 0.08 * std::sin(2 * std::numbers::pi * G / 100.0 + 1.0);
    CHECK(strikes[i] - strikes[i - 1] == Approx(1.0 / (1.8 * std::sqrt(q))).epsilon(1e-3));
    ++checked;
  }
  CHECK(checked > 100);
  // A turn while walking is refused.
  CHECK_THROWS_AS(WalkTrajectory([&] {
                    WalkOptions bad = o;
                    bad.turns = {{29.5, 1.5, true}};  // still walking
                    return bad;
                  }()),
                  std::invalid_argument);
}
