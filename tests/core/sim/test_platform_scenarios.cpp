// Issue 16 part 5: the drone and robot scenarios (no gait, rotor vibration, height, biased
// staggered UWB ranges, one anchor in NLOS for a while).
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>

#include "core/sim/simulator.hpp"

using namespace luxloc;
using namespace luxloc::sim;

TEST_CASE("Drone scenario flies without a gait at 0.5-1.7 m with vibration on the IMU", "[sim][platform]") {
  SimOptions o;
  o.seed = 1;
  const Simulator sim(make_scenario("drone"), o);
  CHECK(sim.step_times().empty());
  double zmin = 1e9, zmax = -1e9;
  for (double t = 0.0; t < sim.duration_s(); t += 0.05) {
    const double z = sim.truth(t).p_BinW.z();
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  CHECK(zmin == Approx(0.5).margin(0.01));
  CHECK(zmax == Approx(1.7).margin(0.01));
  // While hovering (t < 2 s) the accelerometer still shakes: vibration, not a still device.
  const std::vector<ImuSample> imu = sim.imu_samples();
  double lo = 1e9, hi = -1e9;
  for (std::size_t k = 0; k < 150; ++k) {
    lo = std::min(lo, imu[k].acc_inB.z());
    hi = std::max(hi, imu[k].acc_inB.z());
  }
  CHECK(hi - lo > 2.0);
}

TEST_CASE("Drone UWB ranges carry the per-anchor bias, take turns at 10 Hz and one anchor is blocked", "[sim][platform][uwb]") {
  SimOptions o;
  o.seed = 2;
  const Simulator sim(make_scenario("drone"), o);
  const std::vector<UwbAnchorBias> biases = sim.uwb_biases();
  REQUIRE(biases.size() == 8);
  for (const UwbAnchorBias& b : biases) {
    CHECK(b.bias_m >= -0.5);
    CHECK(b.bias_m <= 0.1);
  }
  const std::vector<SimUwbMeasurement> ms = sim.uwb_measurements();
  std::map<int, std::vector<double>> errors;  // LOS range errors per anchor
  std::map<int, int> count, blocked_nlos, blocked_total;
  TimeNs t_prev = 0;
  for (const SimUwbMeasurement& m : ms) {
    CHECK(m.sample.t >= t_prev);  // time order, distinct epochs per anchor
    t_prev = m.sample.t;
    ++count[m.sample.anchor];
    const double t = ns_to_seconds(m.sample.t);
    if (m.sample.anchor == 3 && t >= 20.0 && t < 40.0) {
      ++blocked_total[3];
      blocked_nlos[3] += m.nlos ? 1 : 0;
    }
    if (!m.nlos) errors[m.sample.anchor].push_back(m.sample.range_m - m.true_range_m);
  }
  CHECK(blocked_nlos[3] == blocked_total[3]);
  CHECK(blocked_total[3] == 200);
  for (const UwbAnchorBias& b : biases) {
    CHECK(count[b.anchor] == 600);  // 10 Hz for 60 s
    std::vector<double>& e = errors[b.anchor];
    std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
    CHECK(e[e.size() / 2] == Approx(b.bias_m).margin(0.01));
  }
  // Different anchors answer at different times (two-way ranging takes turns).
  CHECK(ms[1].sample.t - ms[0].sample.t == seconds_to_ns(0.0125));
}

TEST_CASE("Robot scenario keeps a constant height and has no steps, the uwb scenario draws no bias", "[sim][platform]") {
  const Simulator robot(make_scenario("robot"), SimOptions{});
  CHECK(robot.step_times().empty());
  for (double t = 0.0; t < robot.duration_s(); t += 1.0) CHECK(robot.truth(t).p_BinW.z() == Approx(0.5).margin(1e-4));
  CHECK(robot.uwb_biases().size() == 6);
  CHECK(Simulator(make_scenario("uwb"), SimOptions{}).uwb_biases().empty());
}
