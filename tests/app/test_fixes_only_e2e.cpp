// Issue 12: a user with only a fix source (a UWB kit's positions, a fix plugin) and no IMU
// must get a result better than the raw fixes, with an honest sigma. The fusion used to
// skip the prediction when no IMU sample had come: the filter then had no process noise,
// collapsed, gated the fixes and re-initialised (25 Hz: 1.30 m RMSE against 0.42 m raw).
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {

void check_fixes_only(const std::string& name, const std::string& rate_sigma, const std::string& filter) {
  const auto dir = test::scratch_dir(name);
  const auto session = dir / "fixes";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --no-frames --duration 60 --seed 41 --fixes " + rate_sigma);
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  std::filesystem::remove(session / "imu.csv");  // no IMU at all
  const auto poses = dir / "poses.csv";
  const auto run = run_luxloc("run --playback '" + session.string() + "' --filter " + filter + " --out '" + poses.string() + "'");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto truth = read_truth_csv((session / "groundtruth.csv").string());
  const EvalResult fused = evaluate(truth, read_pose_file(poses.string()));
  const EvalResult raw = evaluate(truth, read_pose_file((session / "fixes.csv").string()));  // t,x,y[,sigma_m]
  WARN(name << ": fused " << fused.rmse_m << " m against raw fixes " << raw.rmse_m << " m, " << 100.0 * fused.consistency
            << " % within the 95 % ellipse");
  CHECK(fused.n > 0);
  CHECK(fused.rmse_m < raw.rmse_m);
  CHECK(fused.consistency >= 0.85);
  if (fused.n >= 200) CHECK(fused.consistency <= 0.995);  // fewer poses: 100 % is likely by chance
  CHECK(fused.mean_sigma_m <= 3.0 * fused.rmse_m);  // not inflated either
  CHECK(fused.n_yaw == 0);  // no IMU: the yaw is unknown, left empty, never a made-up 0
  CHECK_THAT(run.output, Catch::Contains("0 gated, 0 re-initialisations"));
}

}  // namespace

TEST_CASE("Fixes only, no IMU, 25 Hz at 0.3 m: the particle filter beats the raw fixes, sigma honest", "[e2e][fixes]") {
  check_fixes_only("fixes_only_25hz", "25:0.3", "pf");
}

TEST_CASE("Fixes only, no IMU, 2 Hz at 0.3 m: the EKF beats the raw fixes, sigma honest", "[e2e][fixes]") {
  check_fixes_only("fixes_only_2hz", "2:0.3", "ekf");
}

TEST_CASE("Fixes only, no IMU, 1 Hz at 0.5 m: the particle filter beats the raw fixes", "[e2e][fixes]") {
  check_fixes_only("fixes_only_1hz", "1:0.5", "pf");
}
