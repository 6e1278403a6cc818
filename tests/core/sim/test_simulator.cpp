// The Simulator: counts and times, determinism per seed, LED phases, blackouts.
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

#include "core/sim/simulator.hpp"

using namespace luxloc;
using namespace luxloc::sim;

TEST_CASE("Simulator counts, times and determinism", "[sim]") {
  SimOptions o;
  o.seed = 3;
  o.duration_s = 4.0;
  const Simulator a(make_scenario("square"), o);
  CHECK(a.duration_s() == 4.0);
  CHECK(a.imu_count() == 400);
  CHECK(a.frame_count() == 120);
  CHECK(a.frame_time_s(0) == Approx(o.frame_offset_s));
  CHECK(a.frame_time_s(30) == Approx(o.frame_offset_s + 1.0));
  CHECK(Simulator(make_scenario("walk"), SimOptions{}).duration_s() == 90.0);  // scenario default

  const Simulator b(make_scenario("square"), o);
  const auto ia = a.imu_samples(), ib = b.imu_samples();
  REQUIRE(ia.size() == ib.size());
  for (std::size_t k = 0; k < ia.size(); ++k) {
    CHECK(ia[k].t == ib[k].t);
    CHECK(ia[k].acc_inB == ib[k].acc_inB);
    CHECK(ia[k].gyro_inB == ib[k].gyro_inB);
  }
  o.seed = 4;
  const Simulator c(make_scenario("square"), o);
  CHECK(c.imu_samples()[10].acc_inB != ia[10].acc_inB);
  CHECK(c.imu_biases().acc != a.imu_biases().acc);
  REQUIRE(a.led_phases_s().size() == a.scenario().map.size());
  for (std::size_t i = 0; i < a.led_phases_s().size(); ++i) {
    CHECK(a.led_phases_s()[i] >= 0.0);
    CHECK(a.led_phases_s()[i] < 1.0 / a.scenario().map.leds()[i].freq_hz);
  }
  CHECK(a.led_phases_s() != c.led_phases_s());
}

TEST_CASE("Blackouts darken exactly the frames that start inside them", "[sim]") {
  SimOptions o;
  o.duration_s = 3.0;
  o.blackouts = {{1.0, 0.5}};
  const Simulator sim(make_scenario("static"), o);
  for (std::size_t k = 0; k < sim.frame_count(); k += 5) {
    const double t = sim.frame_time_s(k);
    const bool dark = t >= 1.0 && t < 1.5;
    CHECK(sim.lights_on(t) == !dark);
    const RenderedFrame f = sim.render(k);
    double mx = 0;
    cv::minMaxLoc(f.gray, nullptr, &mx);
    INFO("frame " << k << " t " << t);
    CHECK(f.leds.empty() == dark);
    CHECK((mx > 100) == !dark);
  }
}

TEST_CASE("Unknown scenarios and bad options are rejected", "[sim]") {
  CHECK_THROWS_WITH(make_scenario("jog"), Catch::Contains("walk") && Catch::Contains("static"));
  SimOptions o;
  o.fps = 0.0;
  CHECK_THROWS_AS(Simulator(make_scenario("walk"), o), std::invalid_argument);
}
