// Issue 11 part 2, end to end (luxloc sim -> run -> eval): the fused yaw of IMU + VLC on
// consumer-grade gyros, its sigma, and a blackout with a 1 deg/s gyro z bias. Seeds 31-33
// are not among the tuning seeds 1-10.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Runs {
  EvalResult fused, ahrs;
  std::string log;
};

// One session, run with the heading state (default) and without (the AHRS yaw; or, given
// `off_args`, with those instead of --no-heading-state).
Runs sim_and_run(const std::string& name, const std::string& sim_args, const std::string& run_args = "",
                 const std::string& off_args = "--no-heading-state") {
  const auto dir = test::scratch_dir(name);
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' " + sim_args);
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  Runs r;
  for (const bool heading : {true, false}) {
    const auto poses = dir / (heading ? "fused.csv" : "ahrs.csv");
    const auto run = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "' " +
                                run_args + (heading ? "" : " " + off_args));
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    if (heading) r.log = run.output;
    (heading ? r.fused : r.ahrs) =
        evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
  }
  return r;
}

double max_error(const EvalResult& r, double t0, double t1) {
  double m = 0.0;
  for (const PoseError& e : r.errors)
    if (const double t = ns_to_seconds(e.t); t >= t0 && t < t1) m = std::max(m, e.err_m);
  return m;
}

double max_yaw_error(const EvalResult& r, double t0, double t1) {
  double m = 0.0;
  for (const PoseError& e : r.errors)
    if (const double t = ns_to_seconds(e.t); t >= t0 && t < t1 && std::isfinite(e.yaw_err_rad))
      m = std::max(m, std::abs(e.yaw_err_rad));
  return m;
}

}  // namespace

TEST_CASE("Fused yaw, consumer gyro, IMU + VLC: p95 <= 1.5 deg, better than the AHRS, sigma_yaw covers it",
          "[e2e][heading]") {
  const Runs r = sim_and_run("heading_consumer", "--scenario walk --seed 31 --imu-grade consumer");
  WARN("fused yaw p95 " << r.fused.yaw_p95_rad / kDeg << " deg (AHRS " << r.ahrs.yaw_p95_rad / kDeg
                        << "), within 1.96 sigma_yaw " << 100.0 * r.fused.yaw_consistency << " %, ATE "
                        << r.fused.rmse_m << " m");
  CHECK(r.fused.yaw_p95_rad <= 1.5 * kDeg);
  CHECK(r.fused.yaw_p95_rad < r.ahrs.yaw_p95_rad);
  CHECK(r.fused.n_sigma_yaw == r.fused.n);  // every pose carries sigma_yaw
  CHECK(r.fused.yaw_consistency >= 0.85);
  CHECK(r.fused.rmse_m <= 0.05);
  CHECK(r.log.find("heading: ") != std::string::npos);
}

TEST_CASE("Fused yaw under a steel pillar and a passing magnet: the camera's heading holds where the AHRS bends",
          "[e2e][heading]") {
  const Runs r = sim_and_run("heading_disturbed", "--scenario walk --seed 32 --imu-grade consumer --mag-disturbance both");
  WARN("fused yaw p95 " << r.fused.yaw_p95_rad / kDeg << " deg, max " << r.fused.yaw_max_rad / kDeg << " (AHRS p95 "
                        << r.ahrs.yaw_p95_rad / kDeg << ")");
  CHECK(r.fused.yaw_p95_rad <= 2.0 * kDeg);
  CHECK(r.fused.yaw_p95_rad < 0.8 * r.ahrs.yaw_p95_rad);
}

TEST_CASE("15 s blackout with a 1 deg/s gyro z bias: <= 0.5 m during, < 10 cm 2 s after, no re-initialisation",
          "[e2e][heading]") {
  const Runs r = sim_and_run(
      "heading_blackout",
      "--scenario walk --seed 33 --imu-grade consumer --gyro-bias-dps 0.3,-0.4,1.0 --mag-disturbance both "
      "--blackout 40:15");
  const double during = max_error(r.fused, 40.0, 55.0), after = max_error(r.fused, 57.0, 58.0);
  WARN("blackout: max " << during << " m during, " << after << " m from 2 s after; yaw p95 "
                        << r.fused.yaw_p95_rad / kDeg << " deg");
  CHECK(during > 0.0);
  CHECK(during <= 0.5);
  CHECK(after < 0.10);
  CHECK(r.log.find(" 0 re-initialisations") != std::string::npos);
}

TEST_CASE("EKF path: the camera's direct yaw from two or more LEDs corrects the heading observer", "[e2e][heading]") {
  const Runs r = sim_and_run("heading_ekf", "--scenario dense --seed 31 --imu-grade consumer --duration 40",
                             "--filter ekf");
  INFO(r.log);
  WARN("EKF fused yaw p95 " << r.fused.yaw_p95_rad / kDeg << " deg (AHRS " << r.ahrs.yaw_p95_rad / kDeg << ")");
  CHECK(r.log.find("camera yaw ") != std::string::npos);
  CHECK(r.fused.yaw_p95_rad < r.ahrs.yaw_p95_rad);
  CHECK(r.fused.yaw_consistency >= 0.8);
}

TEST_CASE("Walker without a camera (one UWB station, 1 Hz fixes): the fused yaw stays with the AHRS's",
          "[e2e][heading]") {
  // The track of a walker observes only the sum of the yaw offset and the walking-direction
  // offset; without the offset's mean reversion for walkers (HeadingNoise::walker_bounded_rad)
  // these sessions' fused yaw p95 was 2-4x the AHRS's: 4.57 vs 1.13 deg (UWB), 3.90 vs 1.73
  // deg (fixes); with it 2.25 and 1.66 deg (gcc Release; the clang sanitizer build, whose
  // particles draw other histories: 2.73 and 1.71 deg). Tolerance over the AHRS per case:
  // between with (the worse of the two builds) and without.
  const std::pair<std::string, double> cases[] = {
      // --walker turning: the stop-28 population these were measured on (stop 29 added side steps).
      {"--scenario uwb --seed 34 --walker turning --imu-grade consumer", 2.0},
      {"--scenario walk --no-frames --fixes 1:0.5 --seed 35 --walker turning --imu-grade consumer --duration 60", 1.0}};
  for (const auto& [args, tolerance_deg] : cases) {
    const Runs r = sim_and_run("heading_no_camera", args);
    WARN(args << ": fused yaw p95 " << r.fused.yaw_p95_rad / kDeg << " deg (AHRS " << r.ahrs.yaw_p95_rad / kDeg
              << "), ATE " << r.fused.rmse_m << " (AHRS yaw " << r.ahrs.rmse_m << ") m, within 1.96 sigma_yaw "
              << 100.0 * r.fused.yaw_consistency << " %");
    CHECK(r.fused.yaw_p95_rad <= r.ahrs.yaw_p95_rad + tolerance_deg * kDeg);
    CHECK(r.fused.rmse_m <= 1.1 * r.ahrs.rmse_m);
    CHECK(r.fused.yaw_consistency >= 0.85);
  }
}

// A walker turning round on the spot (`sim --walker random`, tuning seed 1: 180 deg in 1.9 s
// at 20 s and in 1.0 s at 38 s, up to 340 deg/s, two LEDs in view during both). Frames were
// read with the attitude of the IMU sample after them (up to 10 ms later) and all rows alike
// (14 ms of rolling-shutter readout): the camera's yaw and the particles' offsets took the
// turn's few degrees in and moved them into the AHRS, 1.9 and 3.1 deg off after the turns
// (FusionOptions::max_attitude_backdate_s, derotate_rows).
// Pinned to `--walker turning`: the stop-28 population this was diagnosed on, before side steps
// and a hand-held lever arm were drawn (stop 29).
TEST_CASE("Turning round on the spot under two LEDs: frames read at their exposure keep the yaw",
          "[e2e][heading][pace]") {
  const Runs r = sim_and_run("heading_turn", "--scenario walk --walker turning --seed 1 --imu-grade consumer", "",
                             "--no-frame-derotation");
  const double after_on = std::max(max_yaw_error(r.fused, 22.0, 23.5), max_yaw_error(r.fused, 39.5, 41.0));
  const double after_off = std::max(max_yaw_error(r.ahrs, 22.0, 23.5), max_yaw_error(r.ahrs, 39.5, 41.0));
  WARN("turns on the spot (seed 1): yaw after the turns " << after_on / kDeg << " deg (" << after_off / kDeg
                                                          << " read at the next IMU sample), p95 "
                                                          << r.fused.yaw_p95_rad / kDeg << " deg ("
                                                          << r.ahrs.yaw_p95_rad / kDeg << ")");
  // Measured (gcc Release / clang -O1 ASan): after the turns 1.77 / 1.86 deg against 3.19 /
  // 2.97 read late; p95 1.12 / 1.33 deg against 2.24 / 1.97.
  CHECK(after_off >= 2.5 * kDeg);  // the case is real
  CHECK(after_on <= 2.2 * kDeg);
  CHECK(r.fused.yaw_p95_rad <= 1.5 * kDeg);
  CHECK(r.fused.yaw_p95_rad < 0.8 * r.ahrs.yaw_p95_rad);
  CHECK(r.fused.rmse_m <= 0.05);
}
