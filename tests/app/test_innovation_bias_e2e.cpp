// Issue 12 part 3, end to end (luxloc sim -> run -> eval): the reported sigma carries the
// persistent bias of the fixes' innovations (core/fusion/innovation_bias.hpp), where the
// filter lags its fixes for seconds. Sessions: the tuning seeds of the population where the
// filter's own spread covered the least of the errors and the term still adds ~2 points
// (fixes 44: 94.9 % without it; UWB: see its test). Until the gait's step-length scale started
// at 0.9 (GaitNoise::scale0; before, 1.0) the filter lagged more: fixes 59 and UWB 9 went
// from 93.3 / 89.6 % to 97.2 / 93.0 % with the term; now from 99.7 / 94.4 % to 100 / 96.1 %.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;

namespace {

struct Both {
  EvalResult on, off;
  std::vector<PoseRow> poses_on, poses_off;
};

Both run_both(const std::filesystem::path& dir, const std::filesystem::path& session, const std::string& run_args) {
  Both b;
  for (const bool on : {true, false}) {
    const auto out = dir / (on ? "on.csv" : "off.csv");
    const auto r = run_luxloc("run --playback '" + session.string() + "' --out '" + out.string() + "' " + run_args +
                              (on ? "" : " --no-innovation-bias"));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    // The summary says how much of the sigma the lag made (and nothing when it is off).
    CHECK((r.output.find("mostly widened by the fixes' persistent innovation") != std::string::npos) == on);
    (on ? b.poses_on : b.poses_off) = read_pose_file(out.string());
    (on ? b.on : b.off) = evaluate(read_truth_csv((session / "groundtruth.csv").string()), (on ? b.poses_on : b.poses_off));
  }
  return b;
}

void check_same_track(const Both& b) {
  REQUIRE(b.poses_on.size() == b.poses_off.size());
  for (std::size_t i = 0; i < b.poses_on.size(); ++i) {
    REQUIRE(b.poses_on[i].p_inW == b.poses_off[i].p_inW);  // only the sigma differs
    REQUIRE(b.poses_on[i].sigma_x >= b.poses_off[i].sigma_x);
  }
}

// Simulates a session (luxloc sim SIM_ARGS), runs it (luxloc run RUN_ARGS) with and without
// the lag term, reports the figures and checks that only the sigma differs.
Both simulate_and_run_both(const std::string& name, const std::string& sim_args, const std::string& run_args = "") {
  const auto dir = test::scratch_dir("innovation_bias_" + name);
  const auto session = dir / "session";
  const auto sim = run_luxloc("sim " + sim_args + " --out '" + session.string() + "'");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  const Both b = run_both(dir, session, run_args);
  WARN(name << ": within the 95 % ellipse " << 100.0 * b.on.consistency << " % (without the lag term "
            << 100.0 * b.off.consistency << " %), mean sigma " << b.on.mean_sigma_m << " m (" << b.off.mean_sigma_m
            << "), ATE " << b.on.rmse_m << " m");
  check_same_track(b);
  return b;
}

}  // namespace

TEST_CASE("Honest sigma: a walker lagging its 1 Hz fixes is reported with the lag", "[e2e][sigma]") {
  const Both b = simulate_and_run_both(
      "fixes", "--scenario walk --no-frames --fixes 1:0.5 --walker steady --imu-grade consumer --seed 44");
  // Measured 95.1 -> 97.3 % (gcc, Release; the turn slowdown as a length); 94.9 -> 97.1 % before
  // it (clang -O1: 95.1 -> 97.3 %). The steady walker: the session this was found on, before
  // the walkers' pace drifted (with the drift the walker lags less, 97.5 -> 99.96 %).
  CHECK(b.on.consistency >= b.off.consistency + 0.015);
  CHECK(b.on.consistency >= 0.95);
  CHECK(b.on.consistency <= 0.995);                  // not inflated into uselessness...
  CHECK(b.on.mean_sigma_m <= 1.0 * b.on.rmse_m);     // ...nor beyond the error's size
}

// The walker of UWB tuning seed 1 needs k ~ 0.85; its run starts from a stale calibration
// of another walker (`--gait-scale 1.2 --gait-scale-sigma 0.1`), so the filter walks ahead of
// the one station's fixes until they pull k down. Without the lag term its sigma covers
// 89.9 % of the poses, with it 93.2 % (gcc, Release; clang -O1, the ASan build: 90.2 ->
// 93.5 %), ATE 0.087 m. From 1.3 the gap was larger (67.6 -> 78.7 %) but the run chaotic
// (ATE 0.227 m with gcc, 0.309 m with clang; 80.4 -> 83.7 %). With the default start the
// session lags little since the turn slowdown is a length (GaitNoise::turn_slowdown0):
// 94.4 -> 95.1 %, too close to tell the term's work from a compiler's rounding.
// Pinned to `--walker turning`: the stop-28 population this was diagnosed on, before side steps
// and a hand-held lever arm were drawn (stop 29).
TEST_CASE("Honest sigma: one UWB station's fixes show the filter's lag", "[e2e][sigma][uwb]") {
  const Both b = simulate_and_run_both("uwb", "--scenario uwb --walker turning --imu-grade consumer --seed 1",
                                       "--gait-scale 1.2 --gait-scale-sigma 0.1");
  CHECK(b.on.consistency >= b.off.consistency + 0.02);
  CHECK(b.on.consistency >= 0.90);
  CHECK(b.on.mean_sigma_m <= 1.0 * b.on.rmse_m);
}
