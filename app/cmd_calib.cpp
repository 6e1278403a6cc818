// `luxloc calib <kind>` (SPEC.md "Command line"): calibration tools, one sub-subcommand per
// kind, each registered by its own add_calib_<kind>() below:
//   imu     gyro bias from a static segment, accelerometer bias and scale from six static
//           orientations (SEEDS.md C.4) -> the YAML that `imu` and `run` take with --imu-calib.
//   camera  chessboard images -> Zhang calibration with bad-view rejection -> camera.yaml
//           (SPEC.md "Camera file"), rolling-shutter row time as entered.
//   rowtime (app/cmd_calib_rowtime.cpp) and ledmap (app/cmd_calib_ledmap.cpp) register
//           themselves through commands.hpp.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/image_folder.hpp"
#include "app/run_session.hpp"
#include "calib/camera_calibrator.hpp"
#include "calib/imu_calibrator.hpp"
#include "core/common/input_error.hpp"
#include "core/vlc/camera_model.hpp"
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

// ---- calib camera ----------------------------------------------------------------------

struct CalibCameraArgs {
  std::string images;
  std::string playback;              // or the frames of a session folder
  std::vector<std::string> sources;  // or a live camera (v4l2:...)
  std::size_t views = 20;            // boards to collect from a stream
  double interval_s = 1.0;           // at least this far apart (s of stream time)
  std::string board = "9x6";
  double square_m = 0.025;
  std::string out;
  double row_time_us = 0.0;
  double exposure_us = 0.0;
  bool free_k3 = false;
  double reject_factor = calib::CameraCalibOptions{}.reject_factor;
};

cv::Size parse_board(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  try {
    if (x == std::string::npos) throw std::invalid_argument("no x");
    std::size_t ua = 0, ub = 0;
    const int w = std::stoi(text.substr(0, x), &ua), h = std::stoi(text.substr(x + 1), &ub);
    if (ua != x || ub != text.size() - x - 1 || w < 2 || h < 2 || w > 100 || h > 100) throw std::invalid_argument("range");
    return {w, h};
  } catch (const std::exception&) {
    throw InputError("--board", 0, "--board", "'" + text + "': expected COLSxROWS inner corners, e.g. 9x6");
  }
}

// Boards from a stream (a session's frames or a live camera): a frame is kept when the board
// is found, at least interval_s after the last kept one, and moved (mean corner shift > 5 % of
// the image width) so the views differ; until `views` are kept or the stream ends.
void collect_board_views(const CalibCameraArgs& a, const calib::CameraCalibOptions& o, std::vector<cv::Mat>& images,
                         std::vector<std::string>& names) {
  RunConfig rc;
  rc.playback = a.playback;
  rc.sources = a.sources;
  OpenedSources opened = open_run_sources(rc);
  std::optional<TimeNs> last_t;
  std::vector<cv::Point2f> last_corners;
  std::size_t frames = 0;
  for_each_frame(
      opened, [&] { return images.size() < a.views; },
      [&](const FrameSample& f) {
        ++frames;
        if (last_t && ns_to_seconds(f.t - *last_t) < a.interval_s) return;
        const std::vector<cv::Point2f> corners = calib::detect_chessboard(f.gray, o);
        if (corners.empty()) return;
        if (!last_corners.empty()) {
          double shift = 0.0;
          for (std::size_t i = 0; i < corners.size(); ++i) shift += cv::norm(corners[i] - last_corners[i]);
          if (shift / static_cast<double>(corners.size()) < 0.05 * f.gray.cols) return;
        }
        char name[48];
        std::snprintf(name, sizeof name, "frame %zu (t %.3f s)", frames, ns_to_seconds(f.t));
        images.push_back(f.gray.clone());
        names.emplace_back(name);
        last_t = f.t;
        last_corners = corners;
        std::fprintf(stderr, "calib camera: view %zu of %zu: %s\n", images.size(), a.views, name);
      });
}

int run_calib_camera(const CalibCameraArgs& a) {
  if ((!a.images.empty()) + (!a.playback.empty()) + (!a.sources.empty()) != 1)
    throw InputError("calib camera", 0, "--images", "give one of --images DIR, --playback DIR or --source SPEC");
  // The camera file's own bounds (CameraModel::plausible_*), checked before the calibration's
  // work; 0 is "not given".
  if (a.row_time_us != 0.0 && !CameraModel::plausible_row_time_us(a.row_time_us))
    throw InputError("calib camera", 0, "--row-time-us", "must be 1-200 us (webcams: 15-45 us; 0: not measured)");
  if (a.exposure_us != 0.0 && !CameraModel::plausible_exposure_us(a.exposure_us))
    throw InputError("calib camera", 0, "--exposure-us", "must be 1-1000000 us (0: not given)");
  calib::CameraCalibOptions o;
  o.board = parse_board(a.board);
  o.square_m = a.square_m;
  o.free_k3 = a.free_k3;
  o.reject_factor = a.reject_factor;
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  const std::string origin = !a.images.empty() ? a.images : !a.playback.empty() ? a.playback : "--source";
  if (!a.images.empty()) {
    for (const fs::path& f : image_files(a.images)) {
      cv::Mat g = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
      if (g.empty()) std::fprintf(stderr, "luxloc: %s: not a readable image, skipped\n", f.string().c_str());
      images.push_back(g);
      names.push_back(f.filename().string());
    }
  } else {
    collect_board_views(a, o, images, names);
  }
  calib::CameraCalibResult r;
  try {
    r = calib::calibrate_camera(images, names, o);
  } catch (const std::invalid_argument& e) {
    throw InputError(origin, 0, a.images.empty() ? "frames" : "--images", e.what());
  }
  // Not entered: left out of the file (a chessboard says nothing of timing), with a note; a
  // reader falls back to 30 us rows / 100 us exposure and knows them for guesses.
  r.camera.row_time_known = a.row_time_us > 0.0;
  r.camera.exposure_known = a.exposure_us > 0.0;
  if (r.camera.row_time_known) r.camera.row_time_s = a.row_time_us * 1e-6;
  if (r.camera.exposure_known) r.camera.exposure_s = a.exposure_us * 1e-6;
  r.camera.save(a.out);

  const CameraModel& c = r.camera;
  std::printf("calib camera: board %dx%d, %.4f m squares, %zu images, %zu boards found, %zu used, %d rounds\n",
              o.board.width, o.board.height, o.square_m, images.size(),
              static_cast<std::size_t>(std::count_if(r.views.begin(), r.views.end(),
                                                     [](const calib::CalibView& v) { return v.found; })),
              r.used(), r.rounds);
  std::printf("  image %dx%d  fx %.3f fy %.3f cx %.3f cy %.3f px\n", c.width, c.height, c.fx, c.fy, c.cx, c.cy);
  std::printf("  distortion k1 %+.5f k2 %+.5f p1 %+.6f p2 %+.6f k3 %+.5f\n", c.dist[0], c.dist[1], c.dist[2], c.dist[3],
              c.dist[4]);
  std::printf("  RMS reprojection error %.3f px (used views)\n", r.rms_px);
  for (const calib::CalibView& v : r.views) {
    if (!v.found)
      std::printf("    %-24s no board\n", v.name.c_str());
    else
      std::printf("    %-24s %.3f px%s\n", v.name.c_str(), v.rms_px, v.used ? "" : "  REJECTED");
  }
  if (a.row_time_us <= 0.0)
    std::printf("  note: --row-time-us not given: no row_time_us written (stripe decoding will assume %.0f us; measure it "
                "with `luxloc calib rowtime --freq HZ --images DIR --camera %s --out %s`)\n",
                r.camera.row_time_s * 1e6, a.out.c_str(), a.out.c_str());
  std::printf("  -> %s\n", a.out.c_str());
  std::fflush(stdout);
  return 0;
}

void add_calib_camera(CLI::App& calib, Action& action) {
  auto args = std::make_shared<CalibCameraArgs>();
  CLI::App* cmd = calib.add_subcommand(
      "camera", "camera calibration from chessboard images (Zhang, OpenCV) -> camera.yaml");
  cmd->add_option("--images", args->images, "folder of chessboard images (png, jpg, ...), read in name order")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--playback", args->playback, "or: the frames of a recorded session")->check(CLI::ExistingDirectory);
  cmd->add_option("--source", args->sources, "or: a live camera, e.g. v4l2:/dev/video0 (show the board in many poses)");
  cmd->add_option("--views", args->views, "boards to collect from --playback / --source")->capture_default_str();
  cmd->add_option("--interval", args->interval_s, "seconds between collected views")->capture_default_str();
  cmd->add_option("--board", args->board, "inner corners COLSxROWS")->capture_default_str();
  cmd->add_option("--square", args->square_m, "square side, m")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--out", args->out, "camera.yaml to write (SPEC.md camera file)")->required();
  cmd->add_option("--row-time-us", args->row_time_us, "rolling-shutter line readout time, us (measured with `calib rowtime`, "
                                                      "or ~1e6 / (fps * total lines), 1-200); not given: left out of the file")
      ->check(CLI::Range(0.0, CameraModel::kMaxRowTimeUs))
      ->capture_default_str();
  cmd->add_option("--exposure-us", args->exposure_us, "exposure time the VLC frames use, us; not given: left out of the file")
      ->check(CLI::Range(0.0, CameraModel::kMaxExposureUs))
      ->capture_default_str();
  cmd->add_flag("--k3", args->free_k3, "estimate k3 too (default: fixed at 0, as OpenCV's calibration sample)");
  cmd->add_option("--reject-factor", args->reject_factor,
                  "drop views whose reprojection error exceeds this many times the median, then recalibrate")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  cmd->footer("Prints the per-image reprojection error; rejected views are marked. Exit 2 when fewer than 5 boards "
              "are found. The mounting (R_body_camera, t_body_camera) is written as identity / zero: edit it.");
  cmd->callback([&action, args] { action = [args] { return run_calib_camera(*args); }; });
}

}  // namespace

void add_calib_command(CLI::App& root, Action& action) {
  CLI::App* calib = root.add_subcommand("calib", "calibration tools: imu, camera, rowtime, ledmap, uwb");
  calib->require_subcommand(1);
  add_calib_imu(*calib, action);
  add_calib_camera(*calib, action);
  add_calib_ledmap(*calib, action);
  add_calib_rowtime(*calib, action);
  add_calib_uwb(*calib, action);
}

}  // namespace luxloc::app
