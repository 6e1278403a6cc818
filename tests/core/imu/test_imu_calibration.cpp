#include <catch2/catch.hpp>

#include "core/common/input_error.hpp"
#include "core/imu/imu_calibration.hpp"
#include "test_support.hpp"

using namespace luxloc;

TEST_CASE("IMU calibration: apply inverts measured = scale * true + bias", "[imu]") {
  ImuCalibration c;
  c.acc_bias = {0.1, 0.2, 0.3};
  c.acc_scale = {1.1, 0.9, 1.0};
  c.gyro_bias = {0.01, 0, -0.01};
  c.mag_bias = {5, 0, 0};
  ImuSample m;
  m.acc_inB = {1.1 * 1 + 0.1, 0.9 * 2 + 0.2, 3 + 0.3};
  m.gyro_inB = {0.01, 0.5, -0.01};
  m.mag_inB = {25, 1, 2};
  m.has_mag = true;
  const ImuSample t = c.apply(m);
  CHECK((t.acc_inB - Eigen::Vector3d(1, 2, 3)).norm() < 1e-12);
  CHECK((t.gyro_inB - Eigen::Vector3d(0, 0.5, 0)).norm() < 1e-12);
  CHECK((t.mag_inB - Eigen::Vector3d(20, 1, 2)).norm() < 1e-12);
  CHECK_FALSE(c.is_identity());
  CHECK(ImuCalibration{}.is_identity());
}

TEST_CASE("IMU calibration YAML: round trip, partial files, bad files name the key", "[imu]") {
  const auto dir = test::scratch_dir("imu_calibration_yaml");
  ImuCalibration c;
  c.acc_bias = {0.12, -0.05, 0.3};
  c.acc_scale = {1.01, 0.99, 1.002};
  c.gyro_bias = {1e-3, -2e-3, 5e-4};
  const std::string p = (dir / "calib.yaml").string();
  save_imu_calibration(p, c, {"six-position", 0.004, 6, 30.0});
  const ImuCalibration back = load_imu_calibration(p);
  CHECK((back.acc_bias - c.acc_bias).norm() < 1e-12);
  CHECK((back.acc_scale - c.acc_scale).norm() < 1e-12);
  CHECK((back.gyro_bias - c.gyro_bias).norm() < 1e-12);
  CHECK(back.mag_scale == Eigen::Vector3d::Ones());
  CHECK_THAT(test::read_text(p), Catch::Contains("method: six-position"));

  test::write_text(dir / "gyro_only.yaml", "%YAML:1.0\n---\ngyro_bias: [0.01, 0.02, 0.03]\n");
  CHECK(load_imu_calibration((dir / "gyro_only.yaml").string()).gyro_bias.z() == Approx(0.03));

  auto error_of = [&](const std::string& name, const std::string& text) {
    test::write_text(dir / name, text);
    try {
      load_imu_calibration((dir / name).string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(error_of("short.yaml", "%YAML:1.0\n---\nacc_bias: [0.1, 0.2]\n"),
             Catch::Contains("short.yaml") && Catch::Contains("'acc_bias'") && Catch::Contains("3 numbers"));
  CHECK_THAT(error_of("text.yaml", "%YAML:1.0\n---\nacc_scale: [1, one, 1]\n"), Catch::Contains("'acc_scale'"));
  CHECK_THAT(error_of("scale.yaml", "%YAML:1.0\n---\nacc_scale: [1, 0.1, 1]\n"),
             Catch::Contains("'acc_scale'") && Catch::Contains("[0.5, 2]"));
  CHECK_THAT(error_of("empty.yaml", "%YAML:1.0\n---\nsomething: 1\n"), Catch::Contains("no calibration keys"));
  CHECK_THAT(error_of("broken.yaml", "%YAML:1.0\n---\nacc_bias: [0.1, \n  : : ]]\n"), Catch::Contains("broken.yaml"));
  CHECK_THAT(error_of("missing.yaml", ""), Catch::Contains("missing.yaml"));
  std::filesystem::remove(dir / "missing.yaml");
  CHECK_THROWS_AS(load_imu_calibration((dir / "missing.yaml").string()), InputError);
}
