// `luxloc calib <kind>` (SPEC.md "Command line"): calibration tools, one sub-subcommand per
// kind, each registered by its own add_calib_<kind>() below:
//   imu     gyro bias from a static segment, accelerometer bias and scale from six static
//           orientations (SEEDS.md C.4) -> the YAML that `imu` and `run` take with --imu-calib.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "calib/imu_calibrator.hpp"
#include "core/common/input_error.hpp"
#include "plugins/playback/imu_csv_source.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

// ---- calib imu -------------------------------------------------------------------------

struct CalibImuArgs {
  std::string in;
  std::string out;
  std::string mode = "six-position";
  double min_static_s = calib::ImuCalibratorOptions{}.min_segment_s;
  double gravity = calib::ImuCalibratorOptions{}.gravity;
};

int run_calib_imu(const CalibImuArgs& a) {
  std::string path = a.in;
  if (fs::is_directory(path)) path = (fs::path(path) / "imu.csv").string();
  ImuCsvSource source(path);
  std::vector<ImuSample> samples;
  SensorData d;
  while (source.next(d))
    if (const ImuSample* s = std::get_if<ImuSample>(&d)) samples.push_back(*s);
  if (samples.empty()) throw InputError(path, 0, "", "no usable IMU sample");

  calib::ImuCalibratorOptions o;
  o.mode = a.mode == "static" ? calib::ImuCalibMode::static_only : calib::ImuCalibMode::six_position;
  o.min_segment_s = a.min_static_s;
  o.gravity = a.gravity;
  calib::ImuCalibrationResult r;
  try {
    r = calib::calibrate_imu(samples, o);
  } catch (const std::invalid_argument& e) {
    throw InputError(path, 0, "", e.what());  // the log does not allow this calibration: exit 2
  }
  save_imu_calibration(a.out, r.calibration, r.info());

  constexpr double deg = 180.0 / std::numbers::pi;
  const ImuCalibration& c = r.calibration;
  std::printf("calib imu (%s): %zu samples from %s, %zu static segments (%.1f s)\n", a.mode.c_str(), samples.size(),
              path.c_str(), r.segments.size(), r.static_seconds);
  std::printf("  gyro bias   %+.5f %+.5f %+.5f rad/s (%+.3f %+.3f %+.3f deg/s)\n", c.gyro_bias.x(), c.gyro_bias.y(),
              c.gyro_bias.z(), c.gyro_bias.x() * deg, c.gyro_bias.y() * deg, c.gyro_bias.z() * deg);
  if (!r.orientations.empty()) {
    std::printf("  orientations:");
    for (const Eigen::Vector3d& m : r.orientations) std::printf(" %s", up_axis_name(m));
    std::printf(" up\n");
    std::printf("  acc bias    %+.4f %+.4f %+.4f m/s^2\n", c.acc_bias.x(), c.acc_bias.y(), c.acc_bias.z());
    std::printf("  acc scale   %.5f %.5f %.5f\n", c.acc_scale.x(), c.acc_scale.y(), c.acc_scale.z());
    std::printf("  residual    %.4f m/s^2 rms over %zu orientations\n", r.accel.residual_rms_mps2,
                r.orientations.size());
  }
  for (const auto& [reason, e] : source.drops().snapshot())
    std::printf("  dropped %llu rows (%s), first: %s\n", static_cast<unsigned long long>(e.count), reason.c_str(),
                e.first_message.c_str());
  std::printf("  -> %s\n", a.out.c_str());
  std::fflush(stdout);
  return 0;
}

void add_calib_imu(CLI::App& calib, Action& action) {
  auto args = std::make_shared<CalibImuArgs>();
  CLI::App* cmd = calib.add_subcommand(
      "imu", "IMU calibration: gyro bias from static segments, accelerometer bias and scale from six orientations");
  cmd->add_option("--in", args->in, "IMU log (SPEC imu.csv) or a session folder holding imu.csv")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--out", args->out, "calibration YAML to write (for --imu-calib)")->required();
  cmd->add_option("--mode", args->mode, "static: gyro bias only; six-position: also accelerometer bias and scale")
      ->check(CLI::IsMember({"static", "six-position"}))
      ->capture_default_str();
  cmd->add_option("--min-static", args->min_static_s, "shortest still segment used, seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--gravity", args->gravity, "local gravity, m/s^2")
      ->check(CLI::Range(9.7, 9.9))
      ->capture_default_str();
  cmd->footer(
      "Six-position procedure: lay the IMU still, for a few seconds each, with +z, -z, +x, -x, +y and -y pointing "
      "up (any order; more orientations help). Model: measured = scale * true + bias per axis. The gyro's scale is "
      "not observable at rest and stays 1. Exit 2 when the log lacks the static segments or orientations.");
  cmd->callback([&action, args] { action = [args] { return run_calib_imu(*args); }; });
}

}  // namespace

void add_calib_command(CLI::App& root, Action& action) {
  CLI::App* calib = root.add_subcommand("calib", "calibration tools: imu, ledmap");
  calib->require_subcommand(1);
  add_calib_imu(*calib, action);
  add_calib_ledmap(*calib, action);
}

}  // namespace luxloc::app
