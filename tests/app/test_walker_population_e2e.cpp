// A drawn walker end to end (issue 12): `sim --walker random` records its draw in
// sim_truth.yaml, and IMU + VLC on a walker the constants were not tuned on (seed 61: not
// among the tuning seeds 1-10) stays within the accuracy the README claims.
#include <catch2/catch.hpp>
#include <string>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

TEST_CASE("sim --walker random: the draw is recorded, IMU + VLC on it within 5 cm RMSE", "[e2e][walker]") {
  const auto dir = test::scratch_dir("walker_random");
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --walker random --seed 61 --imu-grade consumer");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  const std::string truth_yaml = test::read_text(session / "sim_truth.yaml");
  CHECK_THAT(truth_yaml, Catch::Contains("walker:") && Catch::Contains("step_length_m") && Catch::Contains("step_hz"));
  const auto poses = dir / "poses.csv";
  const auto run = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "'");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const EvalResult e = evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
  WARN("random walker (seed 61): ATE RMSE " << e.rmse_m << " m, p95 " << e.p95_m << ", max " << e.max_m << ", "
                                            << 100.0 * e.consistency << " % within the 95 % ellipse");
  CHECK(e.rmse_m <= 0.05);
  CHECK(e.p95_m <= 0.10);
  CHECK(e.consistency >= 0.75);
  // A walker cannot be drawn for a scenario without one.
  const auto bad = run_luxloc("sim --out '" + (dir / "x").string() + "' --scenario static --walker random");
  CHECK(bad.exit_code != 0);
  CHECK_THAT(bad.output, Catch::Contains("no walker"));
}
