// Issue 3's fusion targets, end to end as a user runs them (luxloc sim -> run -> eval):
// IMU + VLC with tight coupling on the 90 s walk, and a 15 s blackout of every light.
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {

EvalResult sim_run_eval(const std::string& name, const std::string& sim_args, const std::string& run_args) {
  const auto dir = test::scratch_dir(name);
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' " + sim_args);
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  const auto poses = dir / "poses.csv";
  const auto run = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "' " + run_args);
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  return evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
}

// Largest error over poses with t in [t0, t1) (seconds).
double max_error(const EvalResult& r, double t0, double t1) {
  double m = 0.0;
  for (const PoseError& e : r.errors) {
    const double t = ns_to_seconds(e.t);
    if (t >= t0 && t < t1) m = std::max(m, e.err_m);
  }
  return m;
}

// A 15 s blackout of every light from `start` on a walk of `duration` seconds: the error
// stays <= 0.5 m throughout and is back under 10 cm 2 s after the lights return (the poses
// from 2 s to 3 s after).
void check_blackout(const std::string& name, double start, double duration) {
  constexpr double kLength = 15.0;
  char sim_args[128];
  std::snprintf(sim_args, sizeof sim_args, "--scenario walk --duration %g --seed 11 --blackout %g:%g", duration, start,
                kLength);
  const EvalResult r = sim_run_eval(name, sim_args, "--seed 3");
  const double during = max_error(r, start, start + kLength);
  const double after = max_error(r, start + kLength + 2.0, start + kLength + 3.0);
  WARN("blackout " << start << ":" << kLength << ": max error during " << during << " m, from 2 s after " << after
                   << " m (ATE RMSE " << r.rmse_m << ")");
  CHECK(during > 0.0);  // poses were written through the blackout
  CHECK(during <= 0.5);
  CHECK(after < 0.10);
}

}  // namespace

TEST_CASE("IMU + VLC, tight coupling, default motion model: ATE RMSE <= 5 cm on the 90 s walk", "[e2e][motion]") {
  const EvalResult r = sim_run_eval("motion_walk90", "--scenario walk --duration 90 --seed 11", "--seed 3");
  WARN("walk 90 s: ATE RMSE " << r.rmse_m << " m, median " << r.median_m << ", p95 " << r.p95_m << ", max "
                              << r.max_m);
  CHECK(r.coverage >= 0.98);
  CHECK(r.rmse_m <= 0.05);
  CHECK(r.max_m < 0.3);
}

TEST_CASE("15 s blackout of all lights: error <= 0.5 m throughout, < 10 cm within 2 s of the lights' return",
          "[e2e][motion]") {
  // The blackout spans corners and the stop at 31 s (standing, then walking off again).
  check_blackout("motion_blackout", 20.0, 45.0);
}

TEST_CASE("15 s blackout over the most turns and a stop (50 s into the walk): error <= 0.5 m, back < 10 cm in 2 s",
          "[e2e][motion]") {
  // Six corners, the stop at 61 s and the walk off again at 63 s before the lights return
  // (docs/MOTION.md: the window that peaked at 0.52 m before the last steps were paid out).
  check_blackout("motion_blackout50", 50.0, 70.0);
}
