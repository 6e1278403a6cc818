// `luxloc sim` as a user runs it: the session folder it writes is complete, readable by the
// project's own readers, deterministic per seed; bad usage exits 2.
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/common/csv_reader.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::read_text;
using luxloc::test::run_luxloc;

namespace {

std::size_t count_rows(const std::filesystem::path& p, const std::vector<std::string>& columns) {
  CsvReader r(p.string());
  std::vector<int> cols;
  for (const std::string& c : columns) cols.push_back(r.require_column(c));
  std::size_t n = 0;
  double last_t = -1.0;
  while (r.next_row()) {
    for (int c : cols)
      if (r.column_name(c) != "file") (void)r.number(c);
    const double t = r.number(cols[0]);
    CHECK(t > last_t);  // in time order
    last_t = t;
    ++n;
  }
  return n;
}

}  // namespace

TEST_CASE("luxloc sim writes a complete, readable session folder", "[sim]") {
  const auto dir = test::scratch_dir("cmd_sim") / "walk5";
  const auto r = run_luxloc("sim --out '" + dir.string() + "' --duration 5 --seed 7 --blackout 2:0.5");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("150 frames") != std::string::npos);
  CHECK(r.output.find("12 LEDs") != std::string::npos);

  CHECK(count_rows(dir / "imu.csv", {"t", "ax", "ay", "az", "gx", "gy", "gz", "mx", "my", "mz"}) == 500);
  CHECK(count_rows(dir / "groundtruth.csv", {"t", "x", "y", "z", "yaw", "roll", "pitch"}) == 500);
  CHECK(count_rows(dir / "frames.csv", {"t", "file"}) == 150);
  CHECK(count_rows(dir / "steps.csv", {"t", "x", "y"}) >= 3);
  const LedMap map = LedMap::load((dir / "ledmap.yaml").string());
  CHECK(map.size() == 12);
  CHECK(map.find_id(12)->freq_hz == Approx(4300.0));
  CHECK(map.find_id(1)->diameter_m == Approx(0.20));
  const CameraModel cam = CameraModel::load((dir / "camera.yaml").string());
  CHECK(cam.width == 640);
  CHECK(cam.fx == Approx(460.0));
  CHECK(cam.row_time_s == Approx(30e-6));
  CHECK(cam.R_CtoB.col(2).z() == Approx(1.0));  // looking up
  cv::FileStorage session((dir / "session.yaml").string(), cv::FileStorage::READ);
  CHECK(static_cast<double>(session["device_height_m"]) == Approx(1.0));

  // Every listed frame exists and is a 640x480 image; blackout frames are dark.
  CsvReader frames((dir / "frames.csv").string());
  const int ct = frames.require_column("t"), cf = frames.require_column("file");
  int dark = 0, lit = 0;
  while (frames.next_row()) {
    const std::string file(frames.field(cf));
    const double t = frames.number(ct);
    if (frames.line() % 10 != 0 && !(t > 1.9 && t < 2.6)) continue;
    const cv::Mat img = cv::imread((dir / file).string(), cv::IMREAD_UNCHANGED);
    REQUIRE(img.type() == CV_8UC1);
    CHECK(img.cols == 640);
    CHECK(img.rows == 480);
    double mx = 0;
    cv::minMaxLoc(img, nullptr, &mx);
    if (t >= 2.0 && t < 2.5) {
      CHECK(mx < 20);
      ++dark;
    } else if (mx > 150) {
      ++lit;
    }
  }
  CHECK(dark == 15);
  CHECK(lit > 10);
}

TEST_CASE("luxloc sim: same seed, identical files, another seed, other noise", "[sim]") {
  const auto base = test::scratch_dir("cmd_sim_seed");
  const auto a = base / "a", b = base / "b", c = base / "c";
  REQUIRE(run_luxloc("sim --out '" + a.string() + "' --duration 2 --seed 5").exit_code == 0);
  REQUIRE(run_luxloc("sim --out '" + b.string() + "' --duration 2 --seed 5").exit_code == 0);
  REQUIRE(run_luxloc("sim --out '" + c.string() + "' --duration 2 --seed 6 --no-frames").exit_code == 0);
  CHECK(read_text(a / "imu.csv") == read_text(b / "imu.csv"));
  CHECK(read_text(a / "groundtruth.csv") == read_text(b / "groundtruth.csv"));
  for (const char* f : {"frames/000000.jpg", "frames/000031.jpg", "frames/000059.jpg"}) CHECK(read_text(a / f) == read_text(b / f));
  CHECK(read_text(a / "imu.csv") != read_text(c / "imu.csv"));
  CHECK(read_text(a / "groundtruth.csv") == read_text(c / "groundtruth.csv"));  // the path is the scenario's
  CHECK_FALSE(std::filesystem::exists(c / "frames.csv"));
  CHECK_FALSE(std::filesystem::exists(c / "frames"));
}

TEST_CASE("luxloc sim --frame-format and other scenarios", "[sim]") {
  const auto dir = test::scratch_dir("cmd_sim_jpeg");
  const auto r = run_luxloc("sim --out '" + dir.string() + "' --scenario static --duration 1");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(read_text(dir / "frames.csv").find("frames/000029.jpg") != std::string::npos);
  CHECK(cv::imread((dir / "frames/000010.jpg").string(), cv::IMREAD_GRAYSCALE).cols == 640);
  // A PNG run into the same folder replaces the JPEG frames.
  REQUIRE(run_luxloc("sim --out '" + dir.string() + "' --scenario square --duration 1 --frame-format png").exit_code == 0);
  CHECK_FALSE(std::filesystem::exists(dir / "frames/000010.jpg"));
  CHECK(std::filesystem::exists(dir / "frames/000010.png"));
}

TEST_CASE("luxloc sim: bad usage exits 2 with a useful message", "[sim]") {
  const auto dir = test::scratch_dir("cmd_sim_bad");
  const auto bad_scenario = run_luxloc("sim --out '" + dir.string() + "' --scenario jog");
  CHECK(bad_scenario.exit_code == 2);
  CHECK(bad_scenario.output.find("walk") != std::string::npos);
  CHECK(bad_scenario.output.find("static") != std::string::npos);
  CHECK(run_luxloc("sim --out '" + dir.string() + "' --blackout 3").exit_code == 2);
  CHECK(run_luxloc("sim --out '" + dir.string() + "' --blackout 3:-1").exit_code == 2);
  CHECK(run_luxloc("sim --out '" + dir.string() + "' --duration -2").exit_code == 2);
  CHECK(run_luxloc("sim --duration 2").exit_code == 2);  // --out is required
  const auto contradiction = run_luxloc("sim --out '" + dir.string() + "' --scenario drone --camera --no-frames");
  CHECK(contradiction.exit_code == 2);
  CHECK(contradiction.output.find("--camera") != std::string::npos);
  CHECK(std::filesystem::is_empty(dir));
}

TEST_CASE("luxloc sim --imu-grade, --mag-disturbance and the explicit IMU options", "[sim]") {
  const auto dir = test::scratch_dir("cmd_sim_imu_grade");
  const auto r = run_luxloc("sim --out '" + dir.string() +
                            "' --scenario static --duration 3 --no-frames --imu-grade consumer --mag-disturbance both "
                            "--gyro-bias-dps 0,0,0.8 --gyro-bias-rw 0.01 --scale-error 0.01 --acc-bias 0.1");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string truth = read_text(dir / "sim_truth.yaml");
  CHECK(truth.find("mag_disturbance: both") != std::string::npos);
  CHECK(truth.find("gyro_scale") != std::string::npos);
  CHECK(truth.find("gyro_bias_end_rps") != std::string::npos);
  CHECK(truth.find("data: [ 0., 0., 1.39626340159546") != std::string::npos);  // 0.8 deg/s in rad/s
  const auto bad = test::scratch_dir("cmd_sim_imu_grade_bad");
  CHECK(run_luxloc("sim --out '" + bad.string() + "' --imu-grade superb").exit_code == 2);
  CHECK(run_luxloc("sim --out '" + bad.string() + "' --mag-disturbance lava").exit_code == 2);
  CHECK(run_luxloc("sim --out '" + bad.string() + "' --gyro-bias-dps 1,2").exit_code == 2);
  CHECK(std::filesystem::is_empty(bad));
}

TEST_CASE("luxloc sim --kidnap: a bad spec or a distance the walk never reaches exits 2 naming --kidnap", "[io][sim]") {
  const auto dir = luxloc::test::scratch_dir("io_cmd_sim_kidnap");
  for (const char* bad : {"--kidnap abc", "--kidnap 10:-1", "--kidnap 2:500"}) {
    const auto r = luxloc::test::run_luxloc("sim --out '" + (dir / "s").string() + "' --scenario walk --duration 5 " + bad);
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains("--kidnap"));
  }
}

TEST_CASE("luxloc sim --walker fast --heel-impact: 12 g heel strikes that luxloc imu replaces and keeps every step", "[sim][impact]") {
  const auto dir = test::scratch_dir("cmd_sim_heel_impact");
  const auto r = run_luxloc("sim --out '" + dir.string() +
                            "' --walker fast --heel-impact 11 --imu-grade consumer --seed 6 --duration 40 --no-frames");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string truth = read_text(dir / "sim_truth.yaml");
  CHECK(truth.find("speed_mps: 1.7") != std::string::npos);
  CHECK(truth.find("heel_impact") != std::string::npos);
  // The accelerometer peaks near 12 g.
  CsvReader imu((dir / "imu.csv").string());
  const int az = imu.require_column("az");
  double peak = 0.0;
  while (imu.next_row()) peak = std::max(peak, imu.number(az));
  CHECK(peak > 11.0 * 9.81);
  CHECK(peak < 16.0 * 9.81);  // within the sensor limits every reader enforces
  const auto imu_run = run_luxloc("imu --in '" + dir.string() + "' --out /dev/null --truth '" +
                                  (dir / "groundtruth.csv").string() + "'");
  INFO(imu_run.output);
  REQUIRE(imu_run.exit_code == 0);
  CHECK_THAT(imu_run.output, Catch::Contains("samples of heel-strike impacts replaced"));
  CHECK_THAT(imu_run.output, !Catch::Contains(" 0 samples of heel-strike impacts replaced"));
  CHECK_THAT(imu_run.output, Catch::Contains("steps found (100.0 %)"));
  // A scenario without a walker has no heel to strike with.
  const auto bad = test::scratch_dir("cmd_sim_heel_impact_bad");
  const auto none = run_luxloc("sim --out '" + bad.string() + "' --scenario drone --heel-impact 5");
  CHECK(none.exit_code == 2);
  CHECK_THAT(none.output, Catch::Contains("--heel-impact"));
  CHECK(run_luxloc("sim --out '" + bad.string() + "' --heel-impact 20").exit_code == 2);  // beyond 14 g
  CHECK(std::filesystem::is_empty(bad));
}
