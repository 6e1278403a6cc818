// Visual odometry as a user runs it: luxloc sim --scenario floor (downward camera, the start
// position in fixes.csv) -> luxloc run --playback --vo -> drift against groundtruth.csv.
#include <catch2/catch.hpp>
#include <filesystem>

#include "core/common/csv_reader.hpp"
#include "core/eval/trajectory_io.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

TEST_CASE("luxloc sim --scenario floor -> run --playback --vo: the start fix is written and VO holds the drift", "[vo][e2e]") {
  const auto dir = test::scratch_dir("e2e_vo");
  const auto session = dir / "floor";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --scenario floor --seed 1 --duration 20");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  // Relative navigation needs a known start: fixes.csv holds it (it was deleted by the
  // branch that removes a stale --fixes file: run then had no poses at all).
  REQUIRE(std::filesystem::exists(session / "fixes.csv"));
  CsvReader fixes((session / "fixes.csv").string());
  int rows = 0;
  while (fixes.next_row()) ++rows;
  CHECK(rows == 1);

  const auto poses = dir / "poses.csv";
  const auto run = run_luxloc("run --playback '" + session.string() + "' --vo --out '" + poses.string() + "' --seed 3");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const auto truth = read_truth_csv((session / "groundtruth.csv").string());
  const auto est = read_pose_file(poses.string());
  REQUIRE(est.size() > 100);
  // Final drift over the distance travelled (seed C's figure).
  double dist = 0.0;
  for (std::size_t i = 1; i < truth.size(); ++i) dist += (truth[i].p_inW.head<2>() - truth[i - 1].p_inW.head<2>()).norm();
  const auto& last = est.back();
  Eigen::Vector2d p_true = truth.back().p_inW.head<2>();
  for (std::size_t i = 1; i < truth.size(); ++i)
    if (truth[i].t >= last.t) {
      p_true = truth[i].p_inW.head<2>();
      break;
    }
  const double drift = (last.p_inW.head<2>() - p_true).norm() / dist;
  WARN("floor VO e2e: " << dist << " m travelled, final drift " << 100.0 * drift << " %");
  CHECK(dist > 8.0);
  CHECK(drift < 0.02);
  CHECK(run.output.find("0 velocity updates used") == std::string::npos);
}
