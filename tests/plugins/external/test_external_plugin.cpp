// External source plugins through the C ABI: the example plugin (plain C, built by the
// project) loads, streams through luxloc run and record; a missing file, a library without
// the entry point and a plugin of another ABI version are refused with clear messages.
#include <catch2/catch.hpp>

#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "plugins/external/external_plugin.hpp"
#include "test_support.hpp"

using namespace luxloc;
using namespace luxloc::test;

TEST_CASE("External plugin: loads, opens, streams IMU and fixes, failures and refusals are reported", "[plugins]") {
  const auto plugin = ExternalPlugin::load(LUXLOC_EXAMPLE_PLUGIN);
  CHECK(plugin->kind() == "example-fixes");
  PluginSource src(plugin, SourceSpec::parse("example-fixes:circle,count=5,rate=100"));
  CHECK(src.name() == "example-fixes:circle");
  int imu = 0, fixes = 0;
  TimeNs last = -1;
  SensorData d;
  while (src.next(d)) {
    CHECK(sample_time(d) >= last);
    last = sample_time(d);
    if (std::holds_alternative<ImuSample>(d)) ++imu;
    if (const auto* f = std::get_if<FixSample>(&d)) {
      ++fixes;
      CHECK((f->p_inW - Eigen::Vector2d(4, 3)).norm() == Approx(1.5));
      CHECK(f->sigma_m == 0.05);
    }
  }
  CHECK(imu == 50);
  CHECK(fixes == 5);
  CHECK(src.failure().empty());

  PluginSource failing(plugin, SourceSpec::parse("example-fixes:circle,count=50,rate=100,fail_after=3"));
  int n = 0;
  while (failing.next(d)) ++n;
  CHECK(n == 33);  // 3 x (10 IMU + 1 fix) before the failure
  CHECK(failing.failure().find("simulated device failure after 3 fixes") != std::string::npos);
  CHECK_THROWS_WITH(PluginSource(plugin, SourceSpec::parse("example-fixes:square")), Catch::Contains("unknown target"));
  // The host refuses what it cannot use and counts it.
  CHECK(src.refuse("fix: non-finite position") == 1);
  CHECK(src.drops().total() == 1);
}

TEST_CASE("External plugin: missing file, no entry point, ABI mismatch are clear input errors", "[plugins]") {
  CHECK_THROWS_WITH(ExternalPlugin::load("/nonexistent/libx.so"), Catch::Contains("no such plugin file"));
  CHECK_THROWS_WITH(ExternalPlugin::load(LUXLOC_BIN), Catch::Contains("cannot load"));  // an executable
  const char* libz = "/lib/x86_64-linux-gnu/libz.so.1";
  if (std::filesystem::exists(libz)) CHECK_THROWS_WITH(ExternalPlugin::load(libz), Catch::Contains("no symbol luxloc_plugin_entry"));
  CHECK_THROWS_WITH(ExternalPlugin::load(LUXLOC_EXAMPLE_PLUGIN_ABI99),
                    Catch::Contains("plugin ABI version 99, this luxloc speaks 1"));
}

TEST_CASE("luxloc run --plugin: the plugin's source kind fuses, errors exit 2", "[plugins][app]") {
  const auto dir = scratch_dir("external_plugin_run");
  const std::string plug = std::string("--plugin '") + LUXLOC_EXAMPLE_PLUGIN + "'";
  const auto r = run_luxloc("run " + plug + " --source example-fixes:circle,count=100,rate=100 --out '" +
                            (dir / "poses.csv").string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("source example-fixes:circle: 1100 samples") != std::string::npos);
  const auto poses = read_pose_file((dir / "poses.csv").string());
  REQUIRE(poses.size() > 40);  // 50 Hz output over the 1 s of fixes
  for (std::size_t i = poses.size() / 2; i < poses.size(); ++i)  // converged on the circle
    CHECK((poses[i].p_inW.head<2>() - Eigen::Vector2d(4, 3)).norm() == Approx(1.5).margin(0.15));
  const auto rec = run_luxloc("record " + plug + " --source example-fixes:circle,count=20,rate=100 --out '" + (dir / "rec").string() + "'");
  INFO(rec.output);
  CHECK(rec.exit_code == 0);
  CHECK(rec.output.find("wrote fixes.csv: 20 rows") != std::string::npos);
  const auto failing = run_luxloc("run " + plug + " --source example-fixes:circle,count=50,rate=100,fail_after=10 -q --out '" +
                                  (dir / "f.csv").string() + "'");
  CHECK(failing.exit_code == 1);
  CHECK(failing.output.find("simulated device failure") != std::string::npos);
  const auto abi = run_luxloc(std::string("run --plugin '") + LUXLOC_EXAMPLE_PLUGIN_ABI99 + "' --source example-fixes:circle");
  CHECK(abi.exit_code == 2);
  CHECK(abi.output.find("ABI version 99") != std::string::npos);
  const auto unknown = run_luxloc("run --source example-fixes:circle");
  CHECK(unknown.exit_code == 2);
  CHECK(unknown.output.find("not available in this build") != std::string::npos);
}
