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

TEST_CASE("Side steps and a device off the turning axis: exact derivatives, moving 90 deg off the heading",
          "[sim][pace]") {
  const Scenario sc = make_scenario("walk");
  REQUIRE(sc.walk);
  WalkOptions o = *sc.walk;
  o.walking = {{2.0, 30.0}, {35.0, std::numeric_limits<double>::infinity()}};
  o.turns = {{31.5, 1.5, true}};
  o.gait.pace_waves = {{0.12, 30.0, 0.0}};
  o.gait.pace_horizon_s = 100.0;
  o.side_steps = {{10.03, 3.04, 0.8, true, 0.5}, {40.0, 2.5, 0.6, false, 0.3}};
  o.lever_arm_m = {0.3, -0.1};
  const WalkTrajectory tr(o);
  // Exact through the side steps' turns and the dips' edges (on panel boundaries).
  for (double t = 0.5; t < 60.0; t += 0.0917) check_derivatives(tr, t);
  const std::vector<PaceDip>& dips = tr.side_steps_in_walked_time();
  REQUIRE(dips.size() == 2);
  for (const PaceDip& d : dips)
    for (double edge : {d.start_s, d.ramp_s, d.duration_s})
      CHECK(std::abs(std::remainder(edge, PaceDrift::kPanel)) < 1e-9);
  // On the first plateau (walked time = t - 2.5 on the first walk's plateau) the walker moves
  // to their left: the turning axis's velocity points 90 deg left of the heading (the device's
  // adds the lever arm turning with the path's corners).
  WalkOptions plain = o, on_axis = o;
  plain.side_steps.clear();
  plain.lever_arm_m.setZero();
  on_axis.lever_arm_m.setZero();
  const WalkTrajectory reference(plain), axis(on_axis);
  for (double t = 10.8; t < 12.2; t += 0.1) {
    INFO("t " << t);
    const BodyState s = axis.state(t);
    const double dir = std::atan2(s.v_BinW.y(), s.v_BinW.x());
    CHECK(std::remainder(dir - s.yaw, 2 * std::numbers::pi) == Approx(std::numbers::pi / 2).margin(0.1));
  }
  // Right on the second: the heading 90 deg left of the motion.
  const BodyState r = axis.state(41.25);
  CHECK(std::remainder(std::atan2(r.v_BinW.y(), r.v_BinW.x()) - r.yaw, 2 * std::numbers::pi) ==
        Approx(-std::numbers::pi / 2).margin(0.1));
  // The side step slows the walk: over it the walker covers less path than without it.
  auto walked = [](const WalkTrajectory& w, double a, double b) {
    return w.path_parameter(b).v - w.path_parameter(a).v;
  };
  CHECK(walked(tr, 10.0, 13.1) < 0.75 * walked(reference, 10.0, 13.1));
  CHECK(walked(tr, 10.0, 13.1) > 0.5 * walked(reference, 10.0, 13.1));
  // Before the first side step the walk is that of the walker without them, the device 0.3 m
  // in front and 0.1 m to the right of the axis.
  const BodyState a = tr.state(8.0), b = reference.state(8.0);
  const Eigen::Vector2d lever = Eigen::Rotation2Dd(b.yaw) * Eigen::Vector2d(0.3, -0.1);
  CHECK((a.p_BinW.head<2>() - b.p_BinW.head<2>() - lever).norm() < 1e-9);
  // The turn round on the spot carries the device along a half circle: it ends 2 x 0.32 m
  // from where it started, on the other side of the axis, and moved meanwhile.
  const BodyState before = tr.state(31.0), after = tr.state(33.5), mid = tr.state(32.25);
  CHECK((after.p_BinW - before.p_BinW).norm() == Approx(2.0 * std::hypot(0.3, 0.1)).margin(1e-3));
  CHECK(mid.v_BinW.head<2>().norm() > 0.5);
  // Side steps outside a walk's plateau are refused.
  CHECK_THROWS_AS(WalkTrajectory([&] {
                    WalkOptions bad = o;
                    bad.side_steps = {{28.0, 2.5, 0.6, true, 0.5}};  // into the stop's ramp
                    return bad;
                  }()),
                  std::invalid_argument);
}
