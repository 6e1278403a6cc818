// Issue 12 part 5: dead reckoning from a known start (`run --start X,Y[,YAW]`, session.yaml
// `start:`), and a run that cannot start says why (exit 2) instead of writing 0 poses.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {

// An IMU-only 60 s walk (the simulator's walk starts at (3, 1) heading east).
std::filesystem::path imu_only_session(const std::string& name) {
  const auto dir = test::scratch_dir(name);
  const auto session = dir / "imu_only";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --no-frames --duration 60 --seed 43");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  return session;
}

}  // namespace

TEST_CASE("run with an IMU and no absolute source or start: exit 2 naming what is missing, no silent 0 poses",
          "[app][start]") {
  const auto session = imu_only_session("start_missing");
  const auto r = run_luxloc("run --playback '" + session.string() + "' --out '" + (session / "p.csv").string() + "'");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("no poses written: the filter never started") && Catch::Contains("--start X,Y") &&
                           Catch::Contains("6000 IMU samples"));
}

TEST_CASE("run --start X,Y,YAW: dead reckoning from the known start along the walk", "[app][start][e2e]") {
  const auto session = imu_only_session("start_cli");
  const auto poses = session / "p.csv";
  const auto r = run_luxloc("run --playback '" + session.string() + "' --start 3,1,0 --start-sigma 0.05 --out '" +
                            poses.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const EvalResult e = evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
  WARN("dead reckoning from --start over 60 s: ATE RMSE " << e.rmse_m << " m, max " << e.max_m << ", "
                                                          << 100.0 * e.consistency << " % within the 95 % ellipse");
  CHECK(e.coverage >= 0.99);  // poses from the first IMU sample on
  CHECK(e.errors.front().err_m < 0.15);
  CHECK(e.max_m < 2.0);  // ~70 m walked: within 3 % of the distance
  CHECK(e.consistency >= 0.85);
  // A malformed start is refused before anything runs.
  const auto bad = run_luxloc("run --playback '" + session.string() + "' --start 3,north --out '" + poses.string() + "'");
  CHECK(bad.exit_code != 0);
  CHECK_THAT(bad.output, Catch::Contains("--start") && Catch::Contains("X,Y or X,Y,YAW"));
}

TEST_CASE("session.yaml start: {x, y, yaw} starts the filter, a broken start is an InputError naming the key",
          "[app][start]") {
  const auto session = imu_only_session("start_yaml");
  const auto yaml = session / "session.yaml";
  const std::string original = test::read_text(yaml);
  test::write_text(yaml, original + "start: { x: 3.0, y: 1.0, yaw: 0.0, sigma_m: 0.05 }\n");
  const auto poses = session / "p.csv";
  const auto r = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const EvalResult e = evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
  CHECK(e.errors.front().err_m < 0.15);
  CHECK(e.max_m < 2.0);
  test::write_text(yaml, original + "start: { x: 3.0, yaw: 0.0 }\n");
  const auto broken = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "'");
  CHECK(broken.exit_code == 2);
  CHECK_THAT(broken.output, Catch::Contains("session.yaml") && Catch::Contains("start.y"));
}
