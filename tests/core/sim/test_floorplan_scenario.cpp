// The building-scale scenario (issue 14): a 60 m x 30 m floor, 400+ LEDs sharing 12 or
// fewer frequencies under the co-visibility rule, a walk that stays on the floor; and the
// kidnap: carried without steps to a place 20 m away, then the walk goes on from there.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/sim/kidnap_trajectory.hpp"
#include "core/sim/scenario.hpp"
#include "core/vlc/led_visibility.hpp"

using namespace luxloc;

TEST_CASE("floorplan scenario: 450 LEDs in 12 classes a level camera never sees twice, a 10-minute walk on the floor",
          "[sim][reuse]") {
  const sim::Scenario s = sim::make_scenario("floorplan");
  CHECK(s.map.size() >= 400);
  CHECK(s.map.classes().size() <= 12);
  CHECK(s.map.reuses_frequencies());
  CHECK_NOTHROW(check_frequency_reuse(s.map, s.camera, s.device_height_m, "floorplan"));
  CHECK(s.map.min_reuse_distance_m() >= co_visibility_distance_m(s.camera, 2.0, 15.0 * M_PI / 180.0));
  CHECK(s.map.min_relative_separation() >= 0.02);
  CHECK(s.duration_s == Approx(600.0));
  double walked = 0.0;
  Eigen::Vector3d last = s.trajectory->state(0.0).p_BinW;
  for (double t = 0.0; t <= s.duration_s; t += 0.5) {
    const Eigen::Vector3d p = s.trajectory->state(t).p_BinW;
    CHECK((p.x() > 1.0 && p.x() < s.room_x_m - 1.0 && p.y() > 1.0 && p.y() < s.room_y_m - 1.0));
    walked += (p - last).head<2>().norm();
    last = p;
  }
  CHECK(walked > 500.0);  // several laps of the corridor and the rooms
  // It starts under an LED.
  const Eigen::Vector2d p0 = s.trajectory->state(0.0).p_BinW.head<2>();
  double nearest = 1e9;
  for (const Led& l : s.map.leds()) nearest = std::min(nearest, (l.p_inW.head<2>() - p0).norm());
  CHECK(nearest < 0.3);
}

TEST_CASE("kidnap: carried smoothly without steps to 20 m away, then the walk goes on from there", "[sim][reuse]") {
  const sim::Scenario s = sim::make_scenario("floorplan");
  sim::KidnapOptions o;
  o.start_s = 60.0;
  o.distance_m = 20.0;
  const sim::KidnapTrajectory k(s.trajectory, o);
  const double dist = (k.put_down().p_BinW - k.pick_up().p_BinW).head<2>().norm();
  CHECK(dist >= 20.0);
  CHECK(dist < 21.0);
  CHECK(k.end_s() - k.start_s() == Approx(dist / o.speed_mps));
  // Continuous position, zero velocity at both ends of the carry, and the carry's
  // velocity is the derivative of its position.
  CHECK((k.state(o.start_s).p_BinW - s.trajectory->state(o.start_s).p_BinW).norm() < 1e-9);
  CHECK(k.state(o.start_s + 1e-6).v_BinW.norm() < 1e-3);
  CHECK((k.state(k.end_s() - 1e-6).p_BinW - k.put_down().p_BinW).norm() < 1e-3);
  const double tm = 0.5 * (k.start_s() + k.end_s());
  const Eigen::Vector3d v_num = (k.state(tm + 1e-4).p_BinW - k.state(tm - 1e-4).p_BinW) / 2e-4;
  CHECK((v_num - k.state(tm).v_BinW).norm() < 1e-5);
  // After the put-down the walk continues where it would have been skip_s later.
  const double t = k.end_s() + 5.0;
  CHECK((k.state(t).p_BinW - s.trajectory->state(t + k.skip_s()).p_BinW).norm() < 1e-9);
  // No steps during the carry, the walk's steps before and after.
  const std::vector<double> steps = k.step_times(k.end_s() + 20.0);
  int during = 0, before = 0, after = 0;
  for (double st : steps) (st < k.start_s() ? before : st < k.end_s() ? during : after)++;
  CHECK(during == 0);
  CHECK(before > 50);
  CHECK(after > 20);
  o.distance_m = 500.0;  // never that far on a 60 m floor
  CHECK_THROWS_AS(sim::KidnapTrajectory(s.trajectory, o), std::invalid_argument);
}
