// `luxloc calib rowtime`: the rolling-shutter row time of a camera mode from one LED blinking
// at a known frequency (calib/row_time_calibration.hpp), from still images, a recorded
// session's frames or a live camera; optionally written into a camera.yaml.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/image_folder.hpp"
#include "app/run_session.hpp"
#include "calib/row_time_calibration.hpp"
#include "core/common/input_error.hpp"
#include "core/vlc/camera_model.hpp"

namespace luxloc::app {
namespace {

struct CalibRowTimeArgs {
  std::string images;
  std::string playback;
  std::vector<std::string> sources;
  std::size_t frames = 30;  // frames to measure from a stream
  calib::RowTimeOptions options;
  std::string camera;  // camera.yaml to start from (--out writes it with the row time)
  std::string out;
};

void print_frame(const std::string& name, const calib::RowTimeFrame& f) {
  if (f.valid)
    std::printf("  %-28s row time %8.4f us +- %.4f  (period %.2f rows, %.1f periods, rows %d-%d)\n", name.c_str(),
                f.row_time_s * 1e6, f.row_time_sigma_s * 1e6, f.period_rows, f.periods, f.first_row, f.last_row);
  else if (f.period_rows > 0.0)
    std::printf("  %-28s refused: %s (period %.2f rows, %.1f periods)\n", name.c_str(), f.reason.c_str(),
                f.period_rows, f.periods);
  else
    std::printf("  %-28s refused: %s\n", name.c_str(), f.reason.c_str());
}

int run_calib_rowtime(const CalibRowTimeArgs& a) {
  if ((!a.images.empty()) + (!a.playback.empty()) + (!a.sources.empty()) != 1)
    throw InputError("calib rowtime", 0, "--images", "give one of --images DIR, --playback DIR or --source SPEC");
  if (!a.out.empty() && a.camera.empty())
    throw InputError("calib rowtime", 0, "--out",
                     "--out needs --camera: the camera.yaml (from `calib camera`) whose row_time_us is set");
  std::optional<CameraModel> camera;
  if (!a.camera.empty()) {
    try {
      camera = CameraModel::load(a.camera);
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(a.camera, 0, "", e.what());
    }
  }
  const calib::RowTimeOptions& o = a.options;
  std::printf("calib rowtime: LED at %.3f Hz, row times searched in [%.1f, %.1f] us\n", o.led_freq_hz,
              o.min_row_time_us, o.max_row_time_us);
  std::vector<calib::RowTimeFrame> frames;
  int size_mismatch = 0;
  const auto measure = [&](const cv::Mat& g, const std::string& name) {
    if (camera && (g.cols != camera->width || g.rows != camera->height)) ++size_mismatch;
    frames.push_back(calib::measure_row_time(g, o));
    print_frame(name, frames.back());
  };
  if (!a.images.empty()) {
    for (const std::filesystem::path& f : image_files(a.images)) {
      const cv::Mat g = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
      if (g.empty()) {
        std::fprintf(stderr, "luxloc: %s: not a readable image, skipped\n", f.string().c_str());
        continue;
      }
      measure(g, f.filename().string());
    }
  } else {
    RunConfig rc;
    rc.playback = a.playback;
    rc.sources = a.sources;
    OpenedSources opened = open_run_sources(rc);
    for_each_frame(
        opened, [&] { return frames.size() < a.frames; },
        [&](const FrameSample& f) {
          char name[48];
          std::snprintf(name, sizeof name, "frame t %.3f s", ns_to_seconds(f.t));
          measure(f.gray, name);
        });
  }
  const calib::RowTimeSummary s = calib::summarize_row_times(frames);
  const std::string origin = !a.images.empty() ? a.images : !a.playback.empty() ? a.playback : "--source";
  if (s.used == 0)
    throw InputError(origin, 0, "frames",
                     "no frame showed enough stripes of the LED (" + std::to_string(s.frames) +
                         " measured): fill more rows with the light (closer, a diffuser), lower the exposure, or "
                         "check --freq");
  std::printf("calib rowtime: %d of %d frames used: row time %.4f us (spread %.4f us, range %.4f-%.4f)\n", s.used,
              s.frames, s.row_time_s * 1e6, s.spread_s * 1e6, s.min_s * 1e6, s.max_s * 1e6);
  if (camera) {
    if (camera->row_time_known)
      std::printf("  %s had row_time_us %.4f: %+.2f %%\n", a.camera.c_str(), camera->row_time_s * 1e6,
                  100.0 * (s.row_time_s - camera->row_time_s) / camera->row_time_s);
    else
      std::printf("  %s had no row_time_us (decoding assumed %.0f us: %+.2f %%)\n", a.camera.c_str(),
                  camera->row_time_s * 1e6, 100.0 * (s.row_time_s - camera->row_time_s) / camera->row_time_s);
    if (size_mismatch > 0)
      std::printf("  warning: %d frames differ in size from the camera file's %dx%d: another mode?\n", size_mismatch,
                  camera->width, camera->height);
  }
  if (!a.out.empty()) {
    camera->row_time_s = s.row_time_s;
    camera->row_time_known = true;
    camera->save(a.out);
    std::printf("  -> %s\n", a.out.c_str());
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

void add_calib_rowtime(CLI::App& calib, Action& action) {
  auto args = std::make_shared<CalibRowTimeArgs>();
  CLI::App* cmd = calib.add_subcommand(
      "rowtime", "rolling-shutter row time from one LED blinking at a known frequency (-> camera.yaml row_time_us)");
  cmd->add_option("--freq", args->options.led_freq_hz, "the LED's blink frequency, Hz")
      ->required()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--images", args->images, "folder of frames (png, jpg, ...) showing the LED")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--playback", args->playback, "or: the frames of a recorded session")->check(CLI::ExistingDirectory);
  cmd->add_option("--source", args->sources, "or: a live camera, e.g. v4l2:/dev/video0,exposure_us=100");
  cmd->add_option("--frames", args->frames, "frames to measure from --playback / --source")->capture_default_str();
  cmd->add_option("--min-us", args->options.min_row_time_us, "shortest row time searched, us")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-us", args->options.max_row_time_us, "longest row time searched, us")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--min-periods", args->options.min_periods, "stripe periods a frame must show to count")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--camera", args->camera, "camera.yaml to compare with (and to update with --out)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args->out, "write --camera with the measured row_time_us to this file (may be the same)");
  cmd->footer(
      "Point the camera at one LED (or a diffuser lit by it) so that it fills many rows, with the short exposure "
      "of your VLC frames; the stripes then repeat every 1 / (freq * row_time) rows. Measure per camera mode "
      "(resolution, frame rate): the row time changes with it. Exit 2 when no frame shows enough stripes.");
  cmd->callback([&action, args] { action = [args] { return run_calib_rowtime(*args); }; });
}

}  // namespace luxloc::app
