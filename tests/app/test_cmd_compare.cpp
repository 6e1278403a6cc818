// `luxloc compare` on a short simulated session with sparse, noisy fixes: every
// configuration runs, the table and its CSV agree, and the fused filters beat both
// single-sensor baselines.
#include <catch2/catch.hpp>
#include <map>
#include <sstream>

#include "test_support.hpp"

using namespace luxloc::test;

namespace {

// config -> ate_rmse_m from compare's --csv.
std::map<std::string, double> read_ate(const std::filesystem::path& csv) {
  std::istringstream in(read_text(csv));
  std::string line;
  std::getline(in, line);
  REQUIRE(line.rfind("config,ate_rmse_m,", 0) == 0);
  std::map<std::string, double> ate;
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    ate[line.substr(0, comma)] = std::stod(line.substr(comma + 1));
  }
  return ate;
}

}  // namespace

TEST_CASE("luxloc compare: seeds' configurations on one session, one table", "[filter][compare]") {
  const auto dir = scratch_dir("cmd_compare");
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --duration 40 --no-frames --fixes 2:0.3 --seed 4");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  REQUIRE(std::filesystem::exists(session / "fixes.csv"));

  const auto csv = dir / "table.csv";
  const auto r = run_luxloc("compare --playback '" + session.string() + "' --particles 1000 --csv '" + csv.string() +
                            "' --keep '" + (dir / "poses").string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  for (const char* name : {"imu-only", "fixes-only", "pf-a", "gpf-b", "gpf", "ekf-c", "best"}) {
    CHECK(r.output.find(std::string("\n") + name + " ") != std::string::npos);
    CHECK(std::filesystem::file_size(dir / "poses" / (std::string(name) + ".csv")) > 1000);
  }
  const auto ate = read_ate(csv);
  REQUIRE(ate.size() == 7);
  // Fix noise is 0.3 m per axis (0.42 m radial rms): the fused filters must do better than
  // the raw fixes and than the fixes alone through a constant-velocity filter; the default
  // beats dead reckoning alone (pedestrian dead reckoning drifts ~0.2 m in these 40 s).
  for (const char* fused : {"pf-a", "gpf-b", "gpf", "ekf-c", "best"}) {
    INFO(fused);
    CHECK(ate.at(fused) < 0.42);
    CHECK(ate.at(fused) < ate.at("fixes-only"));
  }
  CHECK(ate.at("best") < ate.at("imu-only"));

  // --only, and an unknown configuration is bad usage.
  const auto one = run_luxloc("compare --playback '" + session.string() + "' --only ekf-c");
  CHECK(one.exit_code == 0);
  CHECK(one.output.find("\nbest ") == std::string::npos);
  CHECK(run_luxloc("compare --playback '" + session.string() + "' --only nope").exit_code == 2);
  CHECK(run_luxloc("compare --playback '" + dir.string() + "'").exit_code == 2);  // no ground truth
}

TEST_CASE("luxloc sim --fixes writes noisy fixes from the truth, on their own random stream", "[sim]") {
  const auto dir = scratch_dir("cmd_sim_fixes");
  REQUIRE(run_luxloc("sim --out '" + (dir / "a").string() + "' --duration 20 --no-frames --fixes 5:0.2").exit_code == 0);
  REQUIRE(run_luxloc("sim --out '" + (dir / "b").string() + "' --duration 20 --no-frames").exit_code == 0);
  CHECK(read_text(dir / "a" / "imu.csv") == read_text(dir / "b" / "imu.csv"));
  CHECK_FALSE(std::filesystem::exists(dir / "b" / "fixes.csv"));
  std::istringstream fixes(read_text(dir / "a" / "fixes.csv"));
  std::string line;
  std::getline(fixes, line);
  CHECK(line == "t,x,y,sigma_m");
  int n = 0;
  while (std::getline(fixes, line)) ++n;
  CHECK(n == 100);
  CHECK(run_luxloc("sim --out '" + (dir / "c").string() + "' --fixes 5").exit_code == 2);
  CHECK(run_luxloc("sim --out '" + (dir / "c").string() + "' --fixes 5:-1").exit_code == 2);
}
