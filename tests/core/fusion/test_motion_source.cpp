// MotionSource (core/fusion/motion_source.cpp): the pdr model's regimes around a stop.
#include <catch2/catch.hpp>
#include <cmath>

#include "core/fusion/motion_source.hpp"
#include "core/imu/sim_walk.hpp"

using namespace luxloc;

TEST_CASE("pdr motion: a walk's last steps are paid out after the walker stops, then nothing moves", "[motion]") {
  // The sim walk stops at 61 s for 2 s (seed 1: at 31 s little is owed). Its last steps are confirmed 0.3 s after their heel
  // strikes, when the bounce has already died: the distance they add must still reach the
  // filter (it was dropped: ~0.2 m short along the walk at every stop).
  const test::SimWalk& w = test::sim_walk(1);
  MotionSource ms;
  TimeNs t_prev = 0;
  bool first = true, stopped = false;
  double output_before_stop = 0.0, paid_still = 0.0, paid_late = 0.0, stop_t = 0.0;
  for (const ImuSample& s : w.imu) {
    const double t = ns_to_seconds(s.t);
    if (t > 62.9) break;
    ms.update(s, w.simulator.truth(t).R_BtoW);
    if (!first) {
      const MotionRegime before = ms.regime();
      const double output_before = ms.gait().output_m();
      const MotionInput u = ms.input(t_prev, s.t);
      if (t > 50.0 && !stopped && before == MotionRegime::gait && ms.regime() == MotionRegime::still) {
        stopped = true;
        stop_t = t;
        output_before_stop = output_before;
      }
      if (stopped && u.has_gait) {
        paid_still += u.gait.speed_mps * u.dt;
        if (t >= 62.3) paid_late += u.gait.speed_mps * u.dt;
      }
      if (stopped) CHECK_FALSE(u.has_acc);  // no strapdown while standing
    }
    first = false;
    t_prev = s.t;
  }
  const double owed = ms.gait().expected_m() - output_before_stop;
  INFO("stepping ended at " << stop_t << " s owing " << owed << " m; paid since " << paid_still << " m");
  REQUIRE(stopped);
  CHECK(stop_t > 60.5);
  CHECK(stop_t < 61.8);
  CHECK(ms.regime() == MotionRegime::still);
  CHECK(owed > 0.05);  // the case is real: the last step was confirmed after the bounce died
  CHECK(paid_still == Approx(owed).margin(0.005));
  CHECK(std::abs(ms.gait().output_m() - ms.gait().expected_m()) < 0.005);
  CHECK(paid_late < 0.005);  // standing still moves nothing once it is paid
}
