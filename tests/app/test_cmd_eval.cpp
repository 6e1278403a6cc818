// `luxloc eval` end to end through the real binary.
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>

#include "test_support.hpp"

using luxloc::test::run_luxloc;
using luxloc::test::scratch_dir;
using luxloc::test::write_text;

namespace {

// Truth: 10 s along x at 1 m/s (10 Hz). Poses: 0.2 m north of it, every 0.25 s.
void write_trajectories(const std::filesystem::path& dir) {
  std::string truth = "t,x,y,z,yaw\n", poses = "t,x,y,z,yaw,sigma_x,sigma_y,roll,pitch,n_eff,leds,mode\n";
  char buf[160];
  for (int i = 0; i <= 100; ++i) {
    std::snprintf(buf, sizeof buf, "%.2f,%.3f,1.0,1.0,0.0\n", 0.1 * i, 0.1 * i);
    truth += buf;
  }
  for (int i = 0; i <= 40; ++i) {
    std::snprintf(buf, sizeof buf, "%.6f,%.5f,1.2,1.0,0.1,0.05,0.05,0,0,,3,fused\n", 0.25 * i, 0.25 * i);
    poses += buf;
  }
  write_text(dir / "groundtruth.csv", truth);
  write_text(dir / "poses.csv", poses);
}

std::string q(const std::filesystem::path& p) {
  std::string s(1, '\'');
  return s.append(p.string()).append(1, '\'');
}

}  // namespace

TEST_CASE("luxloc eval: prints the metrics and the summary line", "[io]") {
  const auto dir = scratch_dir("io_cmd_eval");
  write_trajectories(dir);
  const auto r = run_luxloc("eval --truth " + q(dir / "groundtruth.csv") + " " + q(dir / "poses.csv"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("ATE RMSE 0.200 m | median 0.200 | p95 0.200 | max 0.200 | n 41 | coverage 100.0 %"));
  CHECK_THAT(r.output, Catch::Contains("yaw RMSE         0.1000 rad"));

  const auto j = run_luxloc("eval --json --truth " + q(dir / "groundtruth.csv") + " " + q(dir / "poses.csv"));
  REQUIRE(j.exit_code == 0);
  CHECK_THAT(j.output, Catch::Contains("\"ate_rmse_m\":0.200000"));
  CHECK_THAT(j.output, Catch::Contains("\"n\":41"));
}

TEST_CASE("luxloc eval --plot writes a readable PNG", "[io]") {
  const auto dir = scratch_dir("io_cmd_eval_plot");
  write_trajectories(dir);
  const auto png = dir / "plot.png";
  const auto r = run_luxloc("eval --truth " + q(dir / "groundtruth.csv") + " " + q(dir / "poses.csv") + " --plot " +
                            q(png));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_COLOR);
  REQUIRE_FALSE(img.empty());
  CHECK(img.cols == 1200);
  CHECK(img.rows == 900);
  // Something was drawn: the estimate's colour (blue-ish BGR) appears.
  int blue = 0;
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) {
      const auto px = img.at<cv::Vec3b>(v, u);
      blue += px[0] > 150 && px[2] < 80;
    }
  CHECK(blue > 200);
}

TEST_CASE("luxloc eval: bad input exits 2 naming the problem", "[io]") {
  const auto dir = scratch_dir("io_cmd_eval_bad");
  write_trajectories(dir);
  const std::string truth = q(dir / "groundtruth.csv");

  write_text(dir / "empty.csv", "t,x,y,z,yaw\n");
  auto r = run_luxloc("eval --truth " + truth + " " + q(dir / "empty.csv"));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("no poses"));

  write_text(dir / "bad.csv", "t,x,y\n1.0,1.0,1.0\n2.0,abc,1.0\n");
  r = run_luxloc("eval --truth " + truth + " " + q(dir / "bad.csv"));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("bad.csv:3: field 'x': not a number: 'abc'"));

  write_text(dir / "late.csv", "t,x,y\n100.0,1.0,1.0\n");
  r = run_luxloc("eval --truth " + truth + " " + q(dir / "late.csv"));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("no poses inside the ground-truth time span"));

  r = run_luxloc("eval --truth " + truth + " " + q(dir / "absent.csv"));
  CHECK(r.exit_code == 2);

  r = run_luxloc("eval --truth " + truth + " " + q(dir / "poses.csv") + " --plot " + q(dir / "no" / "dir" / "x.png"));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("x.png"));
}

TEST_CASE("luxloc eval --from/--to/--settle: a window of the poses and when the error settles", "[io]") {
  // Truth along x at 1 m/s; the estimate 5 m off until 3 s, 0.5 m off until 6 s, then 0.1 m.
  const auto dir = scratch_dir("io_cmd_eval_settle");
  std::string truth = "t,x,y\n", poses = "t,x,y\n";
  char buf[96];
  for (int i = 0; i <= 100; ++i) {
    std::snprintf(buf, sizeof buf, "%.2f,%.3f,0\n", 0.1 * i, 0.1 * i);
    truth += buf;
    const double t = 0.1 * i, off = t < 3.0 ? 5.0 : t < 6.0 ? 0.5 : 0.1;
    std::snprintf(buf, sizeof buf, "%.2f,%.3f,%.3f\n", t, t, off);
    poses += buf;
  }
  write_text(dir / "groundtruth.csv", truth);
  write_text(dir / "poses.csv", poses);
  const std::string files = " --truth " + q(dir / "groundtruth.csv") + " " + q(dir / "poses.csv");
  const auto a = run_luxloc("eval --settle 0.2" + files);
  INFO(a.output);
  CHECK_THAT(a.output, Catch::Contains("settled          below 0.2 m from t = 6.00 s (6.00 s after the first evaluated pose)"));
  const auto b = run_luxloc("eval --settle 1 --from 2 --json" + files);
  INFO(b.output);
  CHECK_THAT(b.output, Catch::Contains("\"settled_t\":3.000000"));
  CHECK_THAT(b.output, Catch::Contains("\"settled_after_s\":1.000000"));
  CHECK_THAT(b.output, Catch::Contains("\"n\":81"));
  const auto c = run_luxloc("eval --settle 0.05 --to 8 --json" + files);  // never below 5 cm
  CHECK_THAT(c.output, Catch::Contains("\"settled_t\":null"));
  const auto bad = run_luxloc("eval --from 5 --to 4" + files);
  CHECK(bad.exit_code == 2);
}
