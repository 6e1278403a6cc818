// The live status line: progress, rates per source, LEDs, spread; redrawn in place, ended by
// a newline; the session span comes from the CSVs' first and last rows.
#include <catch2/catch.hpp>
#include <cstdio>

#include "plugins/output/status_line.hpp"
#include "test_support.hpp"

using namespace luxloc;

TEST_CASE("Status line: progress bar, per-source rates, LEDs, spread", "[io]") {
  auto counters = std::make_shared<SampleCounters>(2);
  StatusLine line({"playback:imu", "playback:frames"}, counters, 10.0, seconds_to_ns(100.0), nullptr);
  PoseEstimate p;
  p.t = seconds_to_ns(105.0);
  p.leds = 2;
  p.sigma_x = 0.03;
  p.sigma_y = 0.04;
  p.mode = "fused";
  for (int i = 0; i < 100; ++i) counters->add(0);
  for (int i = 0; i < 30; ++i) counters->add(1);
  const std::string s = line.render(p, 1.0);
  CHECK(s.find("[##########..........] 50% t 5.0 s") == 0);
  CHECK(s.find("playback:imu 100/s") != std::string::npos);
  CHECK(s.find("playback:frames 30/s") != std::string::npos);
  CHECK(s.find("LEDs 2") != std::string::npos);
  CHECK(s.find("sigma 0.05 m") != std::string::npos);
  CHECK(s.find("fused") != std::string::npos);
}

TEST_CASE("Status line: drawn in place with carriage returns, one newline at the end, session span", "[io]") {
  const auto dir = test::scratch_dir("status_line");
  std::FILE* f = std::fopen((dir / "err.txt").c_str(), "w");
  REQUIRE(f);
  {
    auto counters = std::make_shared<SampleCounters>(1);
    StatusLine line({"sim:walk"}, counters, 0.0, 0, f);
    PoseEstimate p;
    line.write(p);
    line.write(p);  // within 250 ms: not redrawn now...
    line.write(p);
    line.flush();   // ...but the last pose is drawn once more before the newline
  }
  std::fclose(f);
  const std::string text = test::read_text(dir / "err.txt");
  CHECK(std::count(text.begin(), text.end(), '\r') == 2);
  CHECK(text.back() == '\n');
  CHECK(text.find('%') == std::string::npos);  // no span: no progress bar
  test::write_text(dir / "imu.csv", "# comment\nt,ax\n10.5,1\n11,1\n12.25,1\n");
  test::write_text(dir / "frames.csv", "t,file\n10.0,a.png\n12.0,b.png\n");
  TimeNs a = 0, b = 0;
  REQUIRE(session_time_span(dir.string(), a, b));
  CHECK(a == seconds_to_ns(10.0));
  CHECK(b == seconds_to_ns(12.25));
}

TEST_CASE("luxloc run --status on draws the status line, off by default into a pipe", "[io][app]") {
  const std::string demo = std::string(LUXLOC_SOURCE_DIR) + "/data/demo-walk";
  const auto dir = test::scratch_dir("status_run");
  const auto on = test::run_luxloc("run --playback '" + demo + "' --out '" + (dir / "p.csv").string() + "' --status on");
  REQUIRE(on.exit_code == 0);
  CHECK(on.output.find("\r[") != std::string::npos);
  CHECK(on.output.find("] 100%") != std::string::npos);
  CHECK(on.output.find("playback:imu") != std::string::npos);
  const auto off = test::run_luxloc("run --playback '" + demo + "' --out '" + (dir / "q.csv").string() + "'");
  REQUIRE(off.exit_code == 0);
  CHECK(off.output.find('\r') == std::string::npos);
}
