// A drawn walker end to end (issue 12): `sim --walker random` records its draw in
// sim_truth.yaml, and IMU + VLC on a walker the constants were not tuned on (seed 61: not
// among the tuning seeds 1-10) stays within the accuracy the README claims.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "core/common/time.hpp"
#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {
// The poses with a <= t < b (s).
std::vector<PoseRow> poses_between(const std::vector<PoseRow>& poses, double a, double b) {
  std::vector<PoseRow> w;
  for (const PoseRow& p : poses)
    if (p.t >= seconds_to_ns(a) && p.t < seconds_to_ns(b)) w.push_back(p);
  return w;
}
// `sim --out DIR/walk SIM_ARGS` (scratch dir `name`), then `run` on it with defaults; the
// session, the simulator's output, the truth and the poses.
struct SimulatedRun {
  std::filesystem::path dir, session;
  std::string sim_output, run_output;
  std::vector<TruthRow> truth;
  std::vector<PoseRow> poses;
};
// `run RUN_ARGS` on r's session into DIR/POSES: r with that run's output and poses.
SimulatedRun run_again(SimulatedRun r, const std::string& run_args, const std::string& poses = "poses.csv") {
  const auto poses_csv = r.dir / poses;
  const auto run =
      run_luxloc("run --playback '" + r.session.string() + "' --out '" + poses_csv.string() + "' " + run_args);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  r.run_output = run.output;
  r.poses = read_pose_file(poses_csv.string());
  return r;
}
SimulatedRun simulate_and_run(const std::string& name, const std::string& sim_args) {
  SimulatedRun r;
  r.dir = test::scratch_dir(name);
  r.session = r.dir / "walk";
  const auto sim = run_luxloc("sim --out '" + r.session.string() + "' " + sim_args);
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  r.sim_output = sim.output;
  r.truth = read_truth_csv((r.session / "groundtruth.csv").string());
  return run_again(std::move(r), "");
}
}  // namespace

TEST_CASE("sim --walker random: the draw is recorded, IMU + VLC on it within 5 cm RMSE", "[e2e][walker]") {
  const SimulatedRun r = simulate_and_run("walker_random", "--walker random --seed 61 --imu-grade consumer");
  const std::string truth_yaml = test::read_text(r.session / "sim_truth.yaml");
  CHECK_THAT(truth_yaml, Catch::Contains("walker:") && Catch::Contains("step_length_m") && Catch::Contains("step_hz") &&
                             Catch::Contains("side_steps:") && Catch::Contains("lever_arm_m:"));
  const EvalResult e = evaluate(r.truth, r.poses);
  WARN("random walker (seed 61): ATE RMSE " << e.rmse_m << " m, p95 " << e.p95_m << ", max " << e.max_m << ", "
                                            << 100.0 * e.consistency << " % within the 95 % ellipse");
  CHECK(e.rmse_m <= 0.05);
  CHECK(e.p95_m <= 0.10);
  CHECK(e.consistency >= 0.75);
  // A walker cannot be drawn for a scenario without one.
  const auto bad = run_luxloc("sim --out '" + (r.dir / "x").string() + "' --scenario static --walker random");
  CHECK(bad.exit_code != 0);
  CHECK_THAT(bad.output, Catch::Contains("no walker"));
}

// Issue 12, 15 s blackout on a drawn walker. Tuning seed 1 sweeps through its turns (0.9 m
// corner rounding, slower in turns than the gait model's 0.2 s/rad): with one step-length
// scale for straights and turns it ran 0.80 m off in the dark; the learnt turn slowdown
// keeps it within 0.28 m, and the widened gait spread keeps the error within the 95 %
// ellipse (100 %; before, the spread of the pinned-down k was too narrow on other seeds).
// Pinned to `--walker turning`: the stop-28 population this was diagnosed on, before side steps
// and a hand-held lever arm were drawn (stop 29).
TEST_CASE("sim --walker turning, 15 s blackout: within 0.5 m in the dark, sigma covers it, 0.1 m 2 s after",
          "[e2e][walker]") {
  const SimulatedRun r =
      simulate_and_run("walker_blackout", "--walker turning --seed 1 --imu-grade consumer --blackout 40:15");
  const auto window = [&](double a, double b) { return evaluate(r.truth, poses_between(r.poses, a, b)); };
  const EvalResult dark = window(40.0, 55.0), after = window(57.0, 58.0), all = evaluate(r.truth, r.poses);
  WARN("blackout (seed 1): max " << dark.max_m << " m, " << 100.0 * dark.consistency
                                 << " % within the 95 % ellipse, mean sigma " << dark.mean_sigma_m << " m; 2-3 s after: max "
                                 << after.max_m << " m");
  REQUIRE(dark.n > 500);
  CHECK(dark.max_m <= 0.5);
  CHECK(dark.consistency >= 0.85);
  // Not inflated (issue 12: mean sigma <= 3x the RMSE, over the session; measured 1.6x).
  CHECK(all.mean_sigma_m <= 3.0 * all.rmse_m);
  CHECK(after.max_m <= 0.10);
}

// The gait fitted to the tracked stretches (core/fusion/gait_regression.hpp): tuning seed 46
// walks into the blackout with a step-length scale and turn slowdown the particles had let
// drift along the line that its turn-heavy last stretch left free; re-centred on the
// least-squares fit the dark stays within 0.26 m (0.66 m without, --no-gait-regression).
// The steady walker (`--walker steady`): the session this was found on, before the walkers'
// pace drifted (with the drift, seed 46 is 0.18 m with the fit and 0.22 m without).
TEST_CASE("sim --walker random, 15 s blackout: the gait fitted to the track carries the walker through the dark",
          "[e2e][walker][gait]") {
  const auto dir = test::scratch_dir("walker_gait_regression");
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() +
                              "' --walker steady --seed 46 --imu-grade consumer --blackout 40:15");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  const auto truth = read_truth_csv((session / "groundtruth.csv").string());
  const auto dark = [&](const std::string& extra) {
    const auto poses_csv = dir / "poses.csv";
    const auto run = run_luxloc("run --playback '" + session.string() + "' --out '" + poses_csv.string() + "' " + extra);
    INFO(run.output);
    REQUIRE(run.exit_code == 0);
    return std::make_pair(evaluate(truth, poses_between(read_pose_file(poses_csv.string()), 40.0, 55.0)), run.output);
  };
  const auto [with, log] = dark("");
  const auto without = dark("--no-gait-regression").first;
  WARN("blackout (seed 46): max in the dark " << with.max_m << " m with the fitted gait, " << without.max_m
                                              << " m without; " << 100.0 * with.consistency << " % within the 95 % ellipse");
  CHECK_THAT(log, Catch::Contains("gait: re-centred on the fit to the tracked stretches"));
  CHECK(with.max_m <= 0.35);
  CHECK(with.max_m < 0.7 * without.max_m);
  CHECK(with.consistency >= 0.85);
}

// Issue 12 part 1: camera modes. A 720p webcam mode (45 us rows, 200 us exposure, 70 deg
// lens; the LED frequencies planned for it, as `calib ledmap plan` would) on a drawn walker
// (tuning seed 3): as accurate as the default VGA camera, the mode recorded in sim_truth.yaml.
// The steady walker (`--walker steady`): with the drifting pace of `--walker random` seed 3
// walks off under its first LED after a 0.5 s gap with the yaw 4 deg off (one LED trades
// yaw against position, docs/MOTION.md "Walkers that change pace and turn round"): 0.075 m.
TEST_CASE("sim --camera-mode 1280x720:45:200:70: IMU + VLC within 5 cm RMSE, sigma covers it", "[e2e][walker][world]") {
  const SimulatedRun r = simulate_and_run(
      "camera_mode_720p", "--walker steady --seed 3 --imu-grade consumer --camera-mode 1280x720:45:200:70");
  CHECK_THAT(r.sim_output, Catch::Contains("camera 1280x720, 45.0 us rows, 200 us exposure"));
  CHECK_THAT(test::read_text(r.session / "sim_truth.yaml"), Catch::Contains("world:") && Catch::Contains("camera-mode"));
  const EvalResult e = evaluate(r.truth, r.poses);
  WARN("720p webcam mode (seed 3): ATE RMSE " << e.rmse_m << " m, p95 " << e.p95_m << ", max " << e.max_m << ", "
                                               << 100.0 * e.consistency << " % within the 95 % ellipse");
  CHECK(e.rmse_m <= 0.05);
  CHECK(e.p95_m <= 0.10);
  CHECK(e.consistency >= 0.85);
  const auto bad = run_luxloc("sim --out '" + (r.dir / "x").string() + "' --camera-mode 1280x720:45");
  CHECK(bad.exit_code != 0);
  CHECK_THAT(bad.output, Catch::Contains("--camera-mode") && Catch::Contains("WxH:ROW_US:EXPOSURE_US"));
}

// A drawn world (tuning seed 7: 1280x720, 31 us rows, 4 LEDs 3.9 m apart on an irregular
// 3.5 m ceiling, an LED in 62 % of the frames). Its first outage comes 4.6 s into the walk:
// fitted on 2 windows of tracked track, the gait regression shifted the particles' k from
// 0.97 to 1.24 (the walker needs 1.01) and the filter ran 0.73 m off in 2 s of dark; with
// GaitRegressionOptions::min_windows the particles keep their own k (max 0.21 m). The steady
// walker (`--walker steady`): the session this was found on, before the walkers' pace
// drifted.
TEST_CASE("sim --world random: sparse lights, the first dark stretch of the walk within 0.4 m", "[e2e][walker][world]") {
  const SimulatedRun r =
      simulate_and_run("world_random", "--walker steady --seed 7 --imu-grade consumer --world random");
  const std::string truth_yaml = test::read_text(r.session / "sim_truth.yaml");
  CHECK_THAT(truth_yaml, Catch::Contains("world:") && Catch::Contains("layout: irregular") &&
                             Catch::Contains("band_hz"));
  const EvalResult e = evaluate(r.truth, r.poses);
  WARN("drawn world (seed 7): ATE RMSE " << e.rmse_m << " m, p95 " << e.p95_m << ", max " << e.max_m << ", "
                                          << 100.0 * e.consistency << " % within the 95 % ellipse");
  CHECK(e.rmse_m <= 0.08);
  CHECK(e.max_m <= 0.4);
  CHECK(e.consistency >= 0.85);
}

// A stop in the dark (720p webcam mode, tuning seed 6: the walker stops at 36.1 s where no
// LED is in view until 44 s). Its last detected step came after the bounce had died; the
// 0.25 m it owed were paid out after the stop and the filter sat 0.2 m past it for 8 s with a
// sigma of 5 cm (no pose of 36-44 s within its 95 % ellipse). With the payout's own noise
// (MotionSourceOptions::stop_owed_sigma) sigma covers it.
TEST_CASE("720p webcam mode, a stop in the dark: sigma covers what the last steps overpaid", "[e2e][walker][world]") {
  const SimulatedRun r = simulate_and_run(
      "camera_mode_stop", "--walker random --seed 6 --imu-grade consumer --camera-mode 1280x720:45:200:70");
  const EvalResult stop = evaluate(r.truth, poses_between(r.poses, 36.5, 44.0)), all = evaluate(r.truth, r.poses);
  WARN("stop in the dark (seed 6): max " << stop.max_m << " m, " << 100.0 * stop.consistency
                                         << " % within the 95 % ellipse; session " << 100.0 * all.consistency << " %");
  REQUIRE(stop.n > 300);
  CHECK(stop.max_m <= 0.3);
  CHECK(stop.consistency >= 0.9);
  CHECK(all.consistency >= 0.9);
}

// A lit world under a high ceiling (tuning seed 30: 1080p, 90 deg lens, 9 lights 3 m above
// the device, ~3 LEDs a frame). The attitude's tilt moves all of them alike, which the
// filter's spread cannot hold: with 0.7 x dz x tilt sigma in quadrature the sigma was 2.5 cm
// against a 4.7 cm error (90 % of the first 40 s within the ellipse); at least the whole
// dz x tilt sigma (FusionOptions::tilt_floor_min) covers it (98 %).
// Pinned to `--walker turning`: the stop-28 population this was diagnosed on, before side steps
// and a hand-held lever arm were drawn (stop 29).
TEST_CASE("sim --world random, a high ceiling seen by a sharp camera: sigma covers the tilt", "[e2e][walker][world]") {
  const SimulatedRun r = simulate_and_run(
      "world_high_ceiling", "--walker turning --seed 30 --imu-grade consumer --world random --duration 40");
  CHECK_THAT(r.sim_output, Catch::Contains("camera 1920x1080"));
  const EvalResult e = evaluate(r.truth, r.poses);
  WARN("high ceiling (world seed 30): ATE RMSE " << e.rmse_m << " m, " << 100.0 * e.consistency
                                                << " % within the 95 % ellipse, mean sigma " << e.mean_sigma_m);
  CHECK(e.rmse_m <= 0.06);
  CHECK(e.consistency >= 0.95);
  CHECK(e.mean_sigma_m <= 3.0 * e.rmse_m);  // not inflated (issue 12)
}

// Issue 12 part 1: the pace drifts within the walk and the walker turns round on the spot.
// Seed 19 turns round (180 deg in 2 s) at 40.2 s, just as a 15 s blackout starts. Without a
// step and with the gyro turning the IMU was not still, so strapdown moved the standing
// walker 0.19 m during the turn and its sigma grew to 1 m; the walk back then ended the dark
// 0.37 m off. With the position held while the specific force is steady
// (MotionSourceOptions::hold_turning_in_place): 0.16 m.
// Pinned to `--walker turning`: the stop-28 population this was diagnosed on, before side steps
// and a hand-held lever arm were drawn (stop 29).
TEST_CASE("sim --walker turning, a turn round on the spot in the dark: held in place, back the way it came",
          "[e2e][walker][pace]") {
  const SimulatedRun r =
      simulate_and_run("walker_turn", "--walker turning --seed 19 --imu-grade consumer --blackout 40:15");
  const std::string truth_yaml = test::read_text(r.session / "sim_truth.yaml");
  CHECK_THAT(truth_yaml, Catch::Contains("pace_waves:") && Catch::Contains("turns:") && Catch::Contains("yaw_deg"));
  const auto window = [&](double a, double b) { return evaluate(r.truth, poses_between(r.poses, a, b)); };
  const EvalResult turn = window(40.0, 43.0), dark = window(40.0, 55.0), after = window(57.0, 58.0);
  WARN("turn on the spot in the dark (seed 19): max " << turn.max_m << " m over the turn, mean sigma "
                                                      << turn.mean_sigma_m << " m; dark max " << dark.max_m << " m, "
                                                      << 100.0 * dark.consistency << " % within the 95 % ellipse");
  REQUIRE(turn.n > 80);
  CHECK(turn.max_m <= 0.05);
  CHECK(turn.mean_sigma_m <= 0.1);  // not the strapdown's 1 m
  CHECK(dark.max_m <= 0.3);
  CHECK(dark.consistency >= 0.85);
  CHECK(after.max_m <= 0.10);
}

// Issue 12 part 1: a drawn walker holds the device off the body's turning axis (tuning seed 4:
// 0.25 m forward, 0.15 m left, sim_truth.yaml lever_arm_m) and turns round on the spot at 28 s,
// before a 15 s blackout with corners in it. Each corner swings the device
// round the walker; the steps carry the body only. Learnt from the turn
// (MotionSourceOptions::lever_arm, core/imu/lever_arm.hpp) the dark ends within 0.34 m;
// without it (--no-lever-arm) 0.90 m off.
TEST_CASE("sim --walker random, the device held off the turning axis: learnt on the spot, carried round the corners",
          "[e2e][walker][lever]") {
  const SimulatedRun on = simulate_and_run("walker_lever", "--walker random --seed 4 --imu-grade consumer --blackout 40:15");
  const SimulatedRun off = run_again(on, "--no-lever-arm", "poses_off.csv");
  CHECK_THAT(on.run_output, Catch::Contains("of the turning axis (from"));
  CHECK_THAT(off.run_output, !Catch::Contains("of the turning axis (from"));
  const auto dark = [](const SimulatedRun& r) { return evaluate(r.truth, poses_between(r.poses, 40.0, 55.0)); };
  const EvalResult d_on = dark(on), d_off = dark(off);
  WARN("lever arm (seed 4): dark max " << d_on.max_m << " m, " << 100.0 * d_on.consistency << " % within the 95 % ellipse ("
                                       << d_off.max_m << " m, " << 100.0 * d_off.consistency << " % not learnt)");
  REQUIRE(d_on.n > 500);
  CHECK(d_on.max_m <= 0.45);
  CHECK(d_on.max_m <= d_off.max_m - 0.3);
  CHECK(d_on.consistency >= 0.85);
}

