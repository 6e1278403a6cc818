// `luxloc eval --html`: a static page with the trajectory vs truth, the error over time and
// the histogram (inline SVG, no script).
#include <catch2/catch.hpp>
#include <cstdio>

#include "test_support.hpp"

using namespace luxloc::test;

TEST_CASE("luxloc eval --html writes a static report: trajectory vs truth, error over time, histogram", "[io]") {
  const auto dir = scratch_dir("eval-html");
  std::string truth = "t,x,y,z,yaw\n", poses = "t,x,y,z,yaw\n";
  char buf[160];
  for (int i = 0; i <= 100; ++i) {
    std::snprintf(buf, sizeof buf, "%.2f,%.3f,1.0,1.0,0.0\n", 0.1 * i, 0.1 * i);
    truth += buf;
  }
  for (int i = 0; i <= 40; ++i) {
    std::snprintf(buf, sizeof buf, "%.6f,%.5f,1.2,1.0,0.1\n", 0.25 * i, 0.25 * i);  // 0.2 m north
    poses += buf;
  }
  write_text(dir / "groundtruth.csv", truth);
  write_text(dir / "poses.csv", poses);
  const auto html = dir / "report.html";
  const auto r = run_luxloc("eval --truth '" + (dir / "groundtruth.csv").string() + "' '" + (dir / "poses.csv").string() +
                            "' --html '" + html.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("html             ") != std::string::npos);
  const std::string page = read_text(html);
  CHECK(page.rfind("<!DOCTYPE html>", 0) == 0);
  CHECK(page.find("<script") == std::string::npos);
  CHECK(page.find("<td>ATE RMSE</td><td>0.200 m</td>") != std::string::npos);
  for (const char* id : {"id=\"trajectory\"", "id=\"error-over-time\"", "id=\"error-histogram\"", "class=\"truth\"",
                         "class=\"est\"", "class=\"err\"", "class=\"bar\""}) {
    INFO(id);
    CHECK(page.find(id) != std::string::npos);
  }
  const auto bad = run_luxloc("eval --truth '" + (dir / "groundtruth.csv").string() + "' '" + (dir / "poses.csv").string() +
                              "' --html /no/such/dir/report.html");
  CHECK(bad.exit_code == 2);
}
