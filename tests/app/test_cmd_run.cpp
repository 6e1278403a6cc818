// `luxloc run` as a user drives it: a config file round trip, and SIGINT mid-session.
#include <catch2/catch.hpp>
#include <array>
#include <cstdio>
#include <sstream>
#include <sys/wait.h>

#include "app/run_session.hpp"
#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "test_support.hpp"

using namespace luxloc::test;

namespace {

const std::string kDemo = std::string(LUXLOC_SOURCE_DIR) + "/data/demo-walk";

std::string line_of(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + "=", 0) == 0) return line;
  return {};
}

}  // namespace

TEST_CASE("luxloc run --dump-config writes a [run] config that --config reads back, flags override it", "[app]") {
  const auto dir = scratch_dir("cmd_run_config");
  const auto dumped = run_luxloc("run --playback '" + kDemo + "' --particles 600 --filter ekf --udp 127.0.0.1:9 --dump-config");
  INFO(dumped.output);
  REQUIRE(dumped.exit_code == 0);
  CHECK(dumped.output.find("[run]") != std::string::npos);
  CHECK(line_of(dumped.output, "particles") == "particles=\"600\"");
  CHECK(line_of(dumped.output, "filter") == "filter=\"ekf\"");
  CHECK(line_of(dumped.output, "udp") == "udp=[\"127.0.0.1:9\"]");
  CHECK(line_of(dumped.output, "realtime") == "realtime=false");
  write_text(dir / "run.toml", dumped.output);

  // Both spellings read the file; a flag given beside it wins.
  for (const std::string& form : {std::string("--config '") + (dir / "run.toml").string() + "' run",
                                  std::string("run --config '") + (dir / "run.toml").string() + "'"}) {
    const auto again = run_luxloc(form + " --particles 700 --dump-config");
    INFO(again.output);
    REQUIRE(again.exit_code == 0);
    CHECK(line_of(again.output, "particles") == "particles=\"700\"");
    CHECK(line_of(again.output, "filter") == "filter=\"ekf\"");
    CHECK(line_of(again.output, "playback") == "playback=\"" + kDemo + "\"");
  }
  // And it runs from the file alone.
  std::string cfg = read_text(dir / "run.toml");
  cfg.replace(cfg.find("udp=[\"127.0.0.1:9\"]"), 19, "out=\"" + (dir / "poses.csv").string() + "\"");
  write_text(dir / "run2.toml", cfg);
  const auto run = run_luxloc("run --config '" + (dir / "run2.toml").string() + "' -q");
  INFO(run.output);
  REQUIRE(run.exit_code == 0);
  CHECK(luxloc::read_pose_file((dir / "poses.csv").string()).size() > 1000);
  CHECK(run_luxloc("run --config '" + (dir / "missing.toml").string() + "'").exit_code == 2);
}

// fuzz_config found it: a switch flag given a value that is no boolean (`--no-uwb=abc`, or
// `no-heading-state=abc` in a config) let std::stoll's invalid_argument out of CLI11: an abort.
TEST_CASE("A switch flag with a value that is not a boolean is bad usage: exit 2 naming the flag", "[app]") {
  const auto dir = scratch_dir("cmd_run_bad_flag");
  write_text(dir / "bad.toml", "[run]\nno-heading-state=fal=se0.1\n");
  for (const std::string& args : {std::string("run --no-uwb=abc"), std::string("run --no-accelerometer=maybe"),
                                  "run --config '" + (dir / "bad.toml").string() + "'"}) {
    const auto r = run_luxloc(args);
    INFO(args << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--no-") != std::string::npos);
  }
  // The values it does read keep their meaning.
  write_text(dir / "ok.toml", "[run]\nno-uwb=true\n");
  const auto ok = run_luxloc("run --config '" + (dir / "ok.toml").string() + "' --dump-config");
  INFO(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(line_of(ok.output, "no-uwb") == "no-uwb=true");
  CHECK(line_of(ok.output, "no-heading-state") == "no-heading-state=false");
  // A switch given as false is off, and the dump says so (read back, it keeps UWB on).
  const auto off = run_luxloc("run --playback '" + kDemo + "' --no-uwb=false --no-heading-state --dump-config");
  INFO(off.output);
  CHECK(off.exit_code == 0);
  CHECK(line_of(off.output, "no-uwb") == "no-uwb=false");
  CHECK(line_of(off.output, "no-heading-state") == "no-heading-state=true");
}

TEST_CASE("SIGINT mid-session: exit 0, a complete parseable CSV with every pose computed", "[app]") {
  const auto dir = scratch_dir("cmd_run_sigint");
  const auto poses = dir / "poses.csv";
  // Real-time playback of the 30 s demo session, interrupted after 2.5 s (a loaded machine
  // under ASan spends over a second starting up; 30 poses need 0.6 s of data).
  const std::string cmd = "sh -c \"'" + std::string(LUXLOC_BIN) + "' run --playback '" + kDemo + "' --realtime --out '" +
                          poses.string() + "' & pid=\\$!; sleep 2.5; kill -INT \\$pid; wait \\$pid; echo rc=\\$?\" 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string output;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) output.append(buf.data(), n);
  pclose(pipe);
  INFO(output);
  CHECK(output.find("rc=0") != std::string::npos);
  CHECK(output.find("luxloc: stopped:") != std::string::npos);
  const std::string text = read_text(poses);
  REQUIRE(!text.empty());
  CHECK(text.back() == '\n');  // no half-written last row
  const auto rows = luxloc::read_pose_file(poses.string());
  // 50 Hz output over ~2.5 s (start-up included), and not the whole session.
  CHECK(rows.size() > 30);
  CHECK(rows.size() < 1000);
  // The report's pose count is what the file holds.
  const auto at = output.find("luxloc: stopped: ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stoul(output.substr(at + 17)) == rows.size());
}

TEST_CASE("run --camera hands a measured row time to a v4l2 source, never the 30 us guess", "[app][v4l2]") {
  const auto dir = scratch_dir("run_row_time");
  const std::string head =
      "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: !!opencv-matrix\n   rows: 3\n"
      "   cols: 3\n   dt: d\n   data: [ 460., 0., 320., 0., 460., 240., 0., 0., 1. ]\n";
  write_text(dir / "measured.yaml", head + "row_time_us: 14.565\n");
  write_text(dir / "guess.yaml", head);
  const auto measured = luxloc::app::measured_row_time_us((dir / "measured.yaml").string());
  REQUIRE(measured.has_value());
  CHECK(*measured == Approx(14.565));
  CHECK_FALSE(luxloc::app::measured_row_time_us((dir / "guess.yaml").string()).has_value());
  write_text(dir / "bad.yaml", head + "row_time_us: -3\n");
  CHECK_THROWS_AS(luxloc::app::measured_row_time_us((dir / "bad.yaml").string()), luxloc::InputError);
  // Beyond a camera's rows (the v4l2 source's own bound is 1-200 us): the camera file and its
  // key are named, not the --source the value would have been handed to.
  write_text(dir / "slow.yaml", head + "row_time_us: 250\n");
  const auto r = run_luxloc("run --source v4l2:/dev/null --camera '" + (dir / "slow.yaml").string() + "' --out '" +
                            (dir / "out.csv").string() + "'");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("slow.yaml") && Catch::Contains("row_time_us") && Catch::Contains("1-200"));
  CHECK_THAT(r.output, !Catch::Contains("--source"));
}
