// `luxloc run --imu-calib FILE`: the calibration of `luxloc calib imu` is applied to every
// IMU sample before the fusion (issue 4: `run` and `imu` both take it).
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/eval/trajectory_io.hpp"
#include "core/eval/trajectory_metrics.hpp"
#include "test_support.hpp"

using namespace luxloc;
using luxloc::test::run_luxloc;
namespace fs = std::filesystem;

namespace {

// Copies imu.csv adding a constant offset to ax and gz (an uncalibrated IMU).
void add_imu_offsets(const fs::path& in, const fs::path& out, double dax, double dgz) {
  std::ifstream f(in);
  std::ofstream o(out);
  std::string line;
  std::getline(f, line);
  o << line << "\n";  // header: t,ax,ay,az,gx,gy,gz,mx,my,mz
  REQUIRE(line.rfind("t,ax,ay,az,gx,gy,gz", 0) == 0);
  while (std::getline(f, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    REQUIRE(v.size() >= 7);
    v[1] += dax;
    v[6] += dgz;
    for (std::size_t i = 0; i < v.size(); ++i) {
      char buf[32];
      std::snprintf(buf, sizeof buf, i == 0 ? "%.6f" : "%.7f", v[i]);
      o << (i ? "," : "") << buf;
    }
    o << "\n";
  }
}

EvalResult run_eval(const fs::path& session, const fs::path& poses, const std::string& extra) {
  const auto r = run_luxloc("run --playback '" + session.string() + "' --out '" + poses.string() + "' --seed 3 " + extra);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  return evaluate(read_truth_csv((session / "groundtruth.csv").string()), read_pose_file(poses.string()));
}

}  // namespace

TEST_CASE("luxloc run --imu-calib removes a known IMU bias, a bad file exits 2", "[e2e][motion][imu]") {
  const auto dir = test::scratch_dir("run_imu_calib");
  const auto session = dir / "walk";
  const auto sim = run_luxloc("sim --out '" + session.string() + "' --scenario walk --duration 20 --seed 4");
  INFO(sim.output);
  REQUIRE(sim.exit_code == 0);
  const EvalResult clean = run_eval(session, dir / "clean.csv", "");

  // The same session from an IMU with a 0.4 m/s^2 accelerometer and a 2 deg/s gyro bias.
  fs::rename(session / "imu.csv", dir / "imu_clean.csv");
  add_imu_offsets(dir / "imu_clean.csv", session / "imu.csv", 0.4, 0.035);
  const EvalResult biased = run_eval(session, dir / "biased.csv", "");
  const auto calib = dir / "imu_calib.yaml";
  test::write_text(calib,
                   "%YAML:1.0\n---\ngyro_bias: [ 0., 0., 0.035 ]\nacc_bias: [ 0.4, 0., 0. ]\n");
  const EvalResult fixed = run_eval(session, dir / "fixed.csv", "--imu-calib '" + calib.string() + "'");
  WARN("clean " << clean.rmse_m << " m, biased " << biased.rmse_m << " m, with --imu-calib " << fixed.rmse_m << " m");
  CHECK(biased.rmse_m > 1.3 * clean.rmse_m);
  CHECK(fixed.rmse_m == Approx(clean.rmse_m).margin(0.005));

  test::write_text(dir / "bad.yaml", "%YAML:1.0\n---\ngyro_bias: [ 0., 0. ]\n");
  const auto bad = run_luxloc("run --playback '" + session.string() + "' --out - --imu-calib '" +
                              (dir / "bad.yaml").string() + "'");
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("gyro_bias") != std::string::npos);
}
