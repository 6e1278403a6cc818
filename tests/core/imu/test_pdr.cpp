#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "core/filter/fast_rng.hpp"
#include "core/imu/mahony_filter.hpp"
#include "core/imu/pdr.hpp"
#include "core/imu/step_matching.hpp"
#include "core/sim/imu_grade.hpp"
#include "core/sim/walk_trajectory.hpp"
#include "core/sim/walker_population.hpp"
#include "sim_walk.hpp"

using namespace luxloc;

namespace {

struct PdrRun {
  StepMatch match;
  double walked_m = 0, end_error_m = 0, distance_m = 0;
  std::vector<Step> steps;
};

PdrRun run_pdr(const test::SimWalk& w, bool use_mag, const PdrOptions& options = {}) {
  MahonyOptions mo;
  mo.use_magnetometer = use_mag;
  MahonyFilter ahrs(mo);
  PedestrianDeadReckoning pdr(options);
  const sim::BodyState start = w.simulator.truth(0.0);
  pdr.set_position(start.p_BinW.head<2>());
  PdrRun r;
  std::vector<double> detected;
  auto take = [&] {
    while (auto s = pdr.pop_step()) {
      detected.push_back(ns_to_seconds(s->t));
      r.steps.push_back(*s);
    }
  };
  for (const ImuSample& s : w.imu) {
    ahrs.update(s);
    pdr.update(s, ahrs.R_BtoW());
    take();
  }
  pdr.finish();
  take();
  r.match = match_steps(detected, w.simulator.step_times());
  const double t_end = ns_to_seconds(w.imu.back().t);
  for (double t = 0.01; t <= t_end + 1e-9; t += 0.01)
    r.walked_m += (w.simulator.truth(t).p_BinW - w.simulator.truth(t - 0.01).p_BinW).head<2>().norm();
  r.end_error_m = (pdr.position() - w.simulator.truth(t_end).p_BinW.head<2>()).norm();
  r.distance_m = pdr.distance_m();
  return r;
}

}  // namespace

TEST_CASE("PDR on the simulated walk: >= 98 % of the steps, <= 2 % false, end within 5 % of the distance", "[imu]") {
  for (const bool mag : {true, false}) {
    const PdrRun r = run_pdr(test::sim_walk(1), mag);
    std::printf("[imu] PDR walk (mag %d): %zu/%zu steps (%.1f %%), %zu false (%.1f %%), walked %.2f m, PDR %.2f m, "
                "end error %.2f m (%.2f %%)\n",
                mag, r.match.matched, r.match.truth, 100 * r.match.recall(), r.match.false_steps(),
                100 * r.match.false_rate(), r.walked_m, r.distance_m, r.end_error_m, 100 * r.end_error_m / r.walked_m);
    CHECK(r.match.truth > 140);
    CHECK(r.match.recall() >= 0.98);
    CHECK(r.match.false_rate() <= 0.02);
    CHECK(r.end_error_m <= 0.05 * r.walked_m);
    // Every step carries usable uncertainty for a particle filter.
    for (const Step& s : r.steps) {
      REQUIRE(s.length_sigma_m > 0.0);
      REQUIRE(s.heading_sigma_rad > 0.0);
      REQUIRE(std::isfinite(s.heading_rad));
    }
  }
}

TEST_CASE("PDR headings follow the walk's legs (first leg heads east)", "[imu]") {
  const PdrRun r = run_pdr(test::sim_walk(1), true);
  REQUIRE(r.steps.size() > 5);
  // The walk starts at (3, 1) heading east along y = 1 to the corner near (7, 1).
  for (int k = 0; k < 4; ++k) CHECK(std::abs(r.steps[k].heading_rad) < 0.06);
}

TEST_CASE("PDR on the slow square walk (0.6 m/s, small swings) keeps the step count", "[imu]") {
  const PdrRun r = run_pdr(test::sim_walk(1, "square"), true);
  CHECK(r.match.recall() >= 0.98);
  CHECK(r.match.false_rate() <= 0.02);
}

namespace {

// The fast walker of `sim --walker fast` (1.7 m/s) on the walk scenario, consumer IMU, with
// heel-strike impacts of `impact_g` (sim --heel-impact).
test::SimWalk fast_walk(std::uint64_t seed, double impact_g) {
  sim::Scenario sc = sim::make_scenario("walk");
  sim::WalkOptions o = sim::apply_walker(*sc.walk, sim::draw_fast_walker(seed, 90.0));
  o.gait.heel_impact_mps2 = impact_g * sim::kGravity;
  sc.trajectory = std::make_shared<sim::WalkTrajectory>(o);
  sim::SimOptions so;
  so.seed = seed;
  so.duration_s = 90.0;
  so.imu = sim::imu_grade("consumer");
  test::SimWalk w{sim::Simulator(std::move(sc), so), {}};
  w.imu = w.simulator.imu_samples();
  return w;
}

}  // namespace

TEST_CASE("PDR on a fast walk (1.7 m/s) with 12 g heel strikes keeps its step count and step length", "[imu][impact]") {
  // Seed 4 (tuning seeds 1-10 of scripts/impact_table.sh): its walk has four stops.
  const test::SimWalk calm = fast_walk(4, 0.0), hit = fast_walk(4, 11.0);
  double peak = 0.0;
  for (const ImuSample& s : hit.imu) peak = std::max(peak, s.acc_inB.norm());
  CHECK(peak > 11.0 * 9.81);  // the accelerometer sees ~12 g
  const PdrRun ref = run_pdr(calm, true), r = run_pdr(hit, true);
  PdrOptions raw;
  raw.impacts.max_jump_mps2 = 0.0;  // the impacts left in
  const PdrRun unfiltered = run_pdr(hit, true, raw);
  std::printf("[imu] fast walk, 12 g heel strikes: %zu/%zu steps, %zu false; PDR %.2f m against %.2f m without "
              "impacts (%.2f m with them left in)\n",
              r.match.matched, r.match.truth, r.match.false_steps(), r.distance_m, ref.distance_m,
              unfiltered.distance_m);
  CHECK(r.match.recall() >= 0.99);
  // The start / stop ramps' small steps land with an impact too (the truth leaves out steps
  // below half the gait): at most one such extra per walk.
  CHECK(r.match.false_steps() <= ref.match.false_steps() + 4);
  CHECK(r.distance_m == Approx(ref.distance_m).epsilon(0.02));
  CHECK(unfiltered.distance_m > 1.2 * ref.distance_m);  // what the filter is for
}

namespace {

// Accelerometer-only samples of a walk at 1.8 steps/s whose device re-orients as it walks
// (a phone turning in a bag: tilt about x swinging +-60 deg over 20 s, and about y by 30 deg),
// gyroscope exactly 0 as in a log without one. Vertical bounce: 2.5 m/s^2 at the cadence.
std::vector<ImuSample> accel_only_walk(double seconds, double rate_hz, double cadence_hz) {
  std::vector<ImuSample> out;
  for (int k = 0; k < static_cast<int>(seconds * rate_hz); ++k) {
    const double t = k / rate_hz;
    const double tilt_x = 1.05 * std::sin(2 * std::numbers::pi * t / 20.0);
    const double tilt_y = 0.52 * std::sin(2 * std::numbers::pi * t / 33.0);
    const Eigen::Matrix3d R_BtoW = (Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
    const double bounce = t < 1.0 ? 0.0 : 2.5 * std::sin(2 * std::numbers::pi * cadence_hz * t);
    ImuSample s;
    s.t = seconds_to_ns(t);
    s.acc_inB = R_BtoW.transpose() * Eigen::Vector3d(0, 0, 9.80665 + bounce);
    out.push_back(s);
  }
  return out;
}

}  // namespace

TEST_CASE("PDR without a gyroscope takes the vertical from the accelerometer and counts the steps of a re-orienting device",
          "[imu]") {
  const double cadence = 1.8, seconds = 60.0;
  const auto samples = accel_only_walk(seconds, 100.0, cadence);
  const auto expected = static_cast<double>(std::floor((seconds - 1.0) * cadence));
  // The attitude an AHRS holds when it has no gyroscope and rejects the off-g accelerometer:
  // stale (here the start's, level).
  PedestrianDeadReckoning pdr;
  for (const auto& s : samples) pdr.update(s, Eigen::Matrix3d::Identity());
  pdr.finish();
  CHECK(pdr.gyro_absent());
  CHECK(std::abs(static_cast<double>(pdr.step_count()) - expected) <= 1.0);

  // The same samples with a working gyroscope (noise only: never exactly 0, 0, 0) and the same
  // stale attitude: the vertical now comes from the attitude, tilted up to 60 deg away from
  // the truth, and steps are lost where the bounce projects too weakly. This is what the
  // gravity window repairs for logs without a gyroscope.
  PedestrianDeadReckoning stale;
  FastRng rng(3);
  for (auto s : samples) {
    s.gyro_inB = 1e-4 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    stale.update(s, Eigen::Matrix3d::Identity());
  }
  stale.finish();
  CHECK_FALSE(stale.gyro_absent());
  CHECK(static_cast<double>(stale.step_count()) < 0.97 * expected);
}
