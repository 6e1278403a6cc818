// End to end, as a user runs it: luxloc sim -> luxloc run --playback -> luxloc eval.
#include <catch2/catch.hpp>
#include <regex>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {

double number_after(const std::string& text, const std::string& label) {
  std::smatch m;
  const std::regex re(label + R"(\s*([0-9.]+))");
  REQUIRE(std::regex_search(text, m, re));
  return std::stod(m[1]);
}

}  // namespace

TEST_CASE("90 s simulated walk: sim -> run --playback -> eval within 0.30 m ATE", "[e2e]") {
  const auto dir = test::scratch_dir("e2e_walk90");
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --scenario walk --duration 90 --seed 11");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);

  const auto poses = dir / "poses.csv";
  const auto run = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "' --seed 3");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  // Playback speed: data seconds per wall second, from the run report.
  const double speed = number_after(run.output, R"(s wall \()");
  WARN("playback speed " << speed << "x real time");

  const auto eval = run_luxloc("eval --truth '" + (session / "groundtruth.csv").string() + "' '" + poses.string() +
                               "' --plot '" + (dir / "plot.png").string() + "'");
  INFO(eval.output);
  REQUIRE(eval.exit_code == 0);
  const EvalResult r = evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
  WARN("ATE RMSE " << r.rmse_m << " m, p95 " << r.p95_m << ", max " << r.max_m << ", coverage " << r.coverage);
  CHECK(r.rmse_m <= 0.30);
  CHECK(r.coverage >= 0.98);  // poses along the whole session
  CHECK(r.max_m < 1.0);
  CHECK(std::filesystem::file_size(dir / "plot.png") > 10000);
}

TEST_CASE("The independent spec-sample session plays back as it is", "[e2e]") {
  const auto fixture = test::shared_dir() / "fixtures" / "spec-sample";
  if (!std::filesystem::exists(fixture)) {
    WARN("no ../shared/fixtures/spec-sample: skipped");
    return;
  }
  const auto dir = test::scratch_dir("e2e_spec_sample");
  const auto poses = dir / "poses.csv";
  const auto run = run_luxloc("run --playback '" + fixture.string() + "' --out '" + poses.string() + "'");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  const EvalResult r = evaluate(read_truth_csv((fixture / "groundtruth.csv").string()), read_pose_file(poses.string()));
  WARN("spec-sample: ATE RMSE " << r.rmse_m << " m, max " << r.max_m << ", coverage " << r.coverage);
  CHECK(r.coverage >= 0.95);
  CHECK(r.rmse_m < 0.15);
}
