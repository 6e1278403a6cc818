// `luxloc imu` end to end: the figures on a simulated session, calibration input, bad
// input, and a live serial IMU through a socat pty.
#include <catch2/catch.hpp>
#include <cstdio>
#include <regex>
#include <thread>

#include "plugins/serial/serial_port.hpp"
#include "plugins/serial/witmotion_parser.hpp"
#include "plugins/serial/socat_pair.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

// The number after `label` in the command output (NaN when absent).
double figure(const std::string& out, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(label + R"(\s*(-?[0-9.]+))"))) return std::nan("");
  return std::stod(m[1]);
}

std::size_t count_lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// A 90 s IMU-only walk in a folder of the calling test case's own: ctest runs test cases as
// parallel processes, and a shared folder would be wiped by one while the other reads it.
std::filesystem::path walk_session(const std::string& name) {
  const auto d = test::scratch_dir(name);
  const auto r = test::run_luxloc("sim --out '" + d.string() + "' --scenario walk --duration 90 --no-frames");
  REQUIRE(r.exit_code == 0);
  return d;
}

}  // namespace

TEST_CASE("luxloc imu on a simulated walk: attitude rows and the done-when figures", "[imu]") {
  const auto dir = walk_session("cmd_imu_walk_1");
  const auto out = dir / "attitude.csv";
  const auto r = test::run_luxloc("imu --in '" + dir.string() + "' --out '" + out.string() + "' --truth '" +
                                  (dir / "groundtruth.csv").string() + "' --steps '" + (dir / "pdr.csv").string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string att = test::read_text(out);
  // SPEC's columns first and in order, then the filter's bias and verdicts.
  CHECK(att.rfind("t,roll,pitch,yaw,qw,qx,qy,qz,bias_gx,bias_gy,bias_gz,mag_rejected,acc_rejected,still\n", 0) == 0);
  CHECK_THAT(r.output, Catch::Contains("rejected magnetometer 0 samples"));
  CHECK(figure(r.output, "yaw error p50") <= 1.0);
  CHECK(figure(r.output, "p95") <= 2.0);
  CHECK(count_lines(att) == 9001);
  CHECK(figure(r.output, "roll rms") <= 1.0);
  CHECK(figure(r.output, "pitch rms") <= 1.0);
  CHECK(std::abs(figure(r.output, "yaw error at the end")) <= 2.0);
  CHECK(figure(r.output, "steps found \\(") >= 98.0);
  CHECK(figure(r.output, "false \\(") <= 2.0);
  CHECK(figure(r.output, "m from the true end \\(") <= 5.0);
  CHECK(count_lines(test::read_text(dir / "pdr.csv")) > 140);

  const auto r2 = test::run_luxloc("imu --in '" + (dir / "imu.csv").string() + "' --out - --no-mag --truth '" +
                                   (dir / "groundtruth.csv").string() + "'");
  INFO(r2.output);
  REQUIRE(r2.exit_code == 0);
  CHECK(figure(r2.output, "roll rms") <= 1.0);
  CHECK(std::abs(figure(r2.output, "yaw error at the end")) <= 5.0);
  CHECK_THAT(r2.output, Catch::Contains("relative to the start"));
}

TEST_CASE("luxloc imu: calibration file, bad input and usage errors exit 2", "[imu]") {
  const auto dir = walk_session("cmd_imu_walk_2");
  const auto tmp = test::scratch_dir("cmd_imu_bad");
  test::write_text(tmp / "calib.yaml", "%YAML:1.0\n---\ngyro_bias: [0.0, 0.0, 0.0]\nacc_scale: [1.0, 1.0, 1.0]\n");
  auto r = test::run_luxloc("imu --in '" + dir.string() + "' --out '" + (tmp / "a.csv").string() + "' --imu-calib '" +
                            (tmp / "calib.yaml").string() + "'");
  CHECK(r.exit_code == 0);
  test::write_text(tmp / "bad.yaml", "%YAML:1.0\n---\nacc_scale: [1.0, 9.0, 1.0]\n");
  r = test::run_luxloc("imu --in '" + dir.string() + "' --out - --imu-calib '" + (tmp / "bad.yaml").string() + "'");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("bad.yaml") && Catch::Contains("acc_scale"));
  test::write_text(tmp / "imu.csv", "t,ax,ay,az,gx,gy\n0,0,0,9.8,0,0\n");
  r = test::run_luxloc("imu --in '" + (tmp / "imu.csv").string() + "' --out -");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("gz"));
  r = test::run_luxloc("imu --out -");
  CHECK(r.exit_code == 2);
  r = test::run_luxloc("imu --source serial-imu:/dev/null,baud=7 --out -");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("baud"));
}

TEST_CASE("luxloc imu --source serial-imu: live WitMotion through a pty, the writer vanishing exits 1", "[imu]") {
  if (!test::SocatPair::available()) {
    WARN("socat not installed: live `luxloc imu` test skipped");
    return;
  }
  const auto dir = test::scratch_dir("cmd_imu_live");
  test::SocatPair pty(dir);
  REQUIRE(pty.running());
  const auto out = dir / "attitude.csv";
  test::CommandResult r;
  std::thread run([&] {
    r = test::run_luxloc("imu --source 'serial-imu:" + pty.b() + ",baud=460800,protocol=witmotion' --out '" +
                         out.string() + "'");
  });
  CHECK(pty.wait_b_opened(std::chrono::seconds(30)));  // luxloc has opened the port (no REQUIRE: `run` must be joined)
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // and set it up (its tcflush drops older bytes)
  {
    SerialPort writer(pty.a(), 460800);
    std::vector<std::uint8_t> bytes;
    for (int k = 0; k < 300; ++k)
      for (const auto& p : {WitMotionParser::encode(0x51, {0, 0, 2048, 0}), WitMotionParser::encode(0x52, {0, 0, 10, 0}),
                            WitMotionParser::encode(0x54, {0, 300, -500, 0})})
        bytes.insert(bytes.end(), p.begin(), p.end());
    writer.write_all(bytes.data(), bytes.size());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  pty.stop();  // the device vanishes
  run.join();
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.output, Catch::Contains("device lost"));
  CHECK(count_lines(test::read_text(out)) == 301);
}

TEST_CASE("luxloc imu --steps on the real phone walks: every carry position within 3 % of the counted steps, 1 % on average",
          "[imu][realdata]") {
  // Six accelerometer-only walks (no gyroscope, no magnetometer) from the Oxford Step Counter
  // data set, one per carry position (../shared/realdata/phone_steps/README.md). Checking data:
  // nothing in the step detector or the gravity window was fitted to them.
  const auto root = test::shared_dir() / "realdata" / "phone_steps";
  if (!std::filesystem::exists(root / "user1_hand" / "imu.csv")) {
    WARN("real data missing: " << root.string());
    return;
  }
  const auto tmp = test::scratch_dir("cmd_imu_phone_steps");
  double sum_abs = 0.0;
  int n = 0;
  for (const char* carry : {"armband", "backpocket", "bag", "frontpocket", "hand", "neckpouch"}) {
    const auto dir = root / (std::string("user1_") + carry);
    const auto steps_csv = tmp / (std::string(carry) + "_steps.csv");
    const auto r = test::run_luxloc("imu --in '" + (dir / "imu.csv").string() + "' --out '" + (tmp / "a.csv").string() +
                                    "' --no-mag --steps '" + steps_csv.string() + "'");
    INFO(carry << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.output, Catch::Contains("no gyroscope for"));
    const double truth = std::stod(test::read_text(dir / "steps.txt"));
    const double detected = static_cast<double>(count_lines(test::read_text(steps_csv))) - 1.0;  // header
    const double err = (detected - truth) / truth;
    INFO(carry << ": " << detected << " steps detected, " << truth << " counted");
    CHECK(std::abs(err) <= 0.03);
    sum_abs += std::abs(err);
    ++n;
  }
  CHECK(sum_abs / n <= 0.01);
}
