// `luxloc calib imu` end to end on a synthetic six-position log with a known error model.
#include <catch2/catch.hpp>
#include <cstdio>

#include "calib/six_position_log.hpp"
#include "core/imu/imu_calibration.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {
void write_imu_csv(const std::filesystem::path& p, const std::vector<ImuSample>& log) {
  std::string s = "t,ax,ay,az,gx,gy,gz\n";
  char line[256];
  for (const ImuSample& x : log) {
    std::snprintf(line, sizeof line, "%.4f,%.6f,%.6f,%.6f,%.7f,%.7f,%.7f\n", ns_to_seconds(x.t), x.acc_inB.x(),
                  x.acc_inB.y(), x.acc_inB.z(), x.gyro_inB.x(), x.gyro_inB.y(), x.gyro_inB.z());
    s += line;
  }
  test::write_text(p, s);
}
}  // namespace

TEST_CASE("luxloc calib imu: six-position log -> YAML within 1 %, which luxloc imu takes", "[imu]") {
  const auto dir = test::scratch_dir("cmd_calib_imu");
  const test::ImuErrorModel truth;
  write_imu_csv(dir / "imu.csv", test::six_position_log(truth));
  const auto yaml = dir / "imu_calib.yaml";
  auto r = test::run_luxloc("calib imu --in '" + (dir / "imu.csv").string() + "' --out '" + yaml.string() + "'");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("+z -z +x -x +y -y up"));
  const ImuCalibration c = load_imu_calibration(yaml.string());
  for (int j = 0; j < 3; ++j) {
    CHECK(std::abs(c.acc_bias[j] - truth.acc_bias[j]) <= 0.01 * std::abs(truth.acc_bias[j]));
    CHECK(std::abs(c.acc_scale[j] - truth.acc_scale[j]) <= 0.01 * truth.acc_scale[j]);
    CHECK(std::abs(c.gyro_bias[j] - truth.gyro_bias[j]) <= 0.01 * std::abs(truth.gyro_bias[j]));
  }
  r = test::run_luxloc("imu --in '" + (dir / "imu.csv").string() + "' --imu-calib '" + yaml.string() + "' --out '" +
                       (dir / "att.csv").string() + "'");
  CHECK(r.exit_code == 0);
  // Static mode on the same log: gyro bias only.
  r = test::run_luxloc("calib imu --mode static --in '" + dir.string() + "' --out '" + (dir / "static.yaml").string() + "'");
  REQUIRE(r.exit_code == 0);
  CHECK(load_imu_calibration((dir / "static.yaml").string()).acc_scale == Eigen::Vector3d::Ones());
}

TEST_CASE("luxloc calib imu: a log without six orientations exits 2 saying what is missing", "[imu]") {
  const auto dir = test::scratch_dir("cmd_calib_imu_bad");
  write_imu_csv(dir / "imu.csv", test::six_position_log({}, 4));
  const auto r = test::run_luxloc("calib imu --in '" + (dir / "imu.csv").string() + "' --out '" +
                                  (dir / "c.yaml").string() + "'");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("found 4 static orientation"));
  CHECK_FALSE(std::filesystem::exists(dir / "c.yaml"));
  CHECK(test::run_luxloc("calib").exit_code == 2);  // a kind is required
}
