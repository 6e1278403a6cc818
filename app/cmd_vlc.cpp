// `luxloc vlc`: a decode report for setting up a real room (docs/VLC.md). Runs the stripe
// decoder over a session's frames (or a live V4L2 camera) and prints what it saw: frames,
// frames with LEDs, blobs, decodes per LED id with the mean frequency and its spread, and
// the rejected blobs by reason. Optional: one CSV row per blob (--out), a window with the
// blobs drawn (--view), single-frame positions by camera geometry (bearing fix with the
// IMU attitude) and by received signal strength (--position), with their errors against
// groundtruth.csv, and the decoder's id accuracy against the simulator's truth (--check-ids).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include "app/commands.hpp"
#include "app/sim_truth.hpp"
#include "core/common/csv_reader.hpp"
#include "core/common/input_error.hpp"
#include "core/imu/mahony_filter.hpp"
#include "core/sim/frame_renderer.hpp"
#include "core/vlc/camera_geometry_fix.hpp"
#include "core/vlc/id_check.hpp"
#include "core/vlc/rss_trilateration.hpp"
#include "core/vlc/stripe_decoder.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/output/text_file.hpp"
#include "plugins/playback/frame_list_source.hpp"
#include "plugins/playback/imu_csv_source.hpp"
#include "plugins/playback/playback_session.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

// The report goes to stdout, or to stderr when the per-blob CSV does (--out -).
std::FILE* g_report = stdout;

struct VlcArgs {
  std::string playback;
  std::string source;
  std::string map_path;
  std::string camera_path;
  std::string out;
  std::string position = "none";
  bool view = false;
  bool truth_attitude = false;
  bool check_ids = false;
  double duration_s = 0.0;
  double rss_c = std::numeric_limits<double>::quiet_NaN();
  double rss_calibrate_s = 0.0;
  double device_height_m = std::numeric_limits<double>::quiet_NaN();
};

// ---- attitude -------------------------------------------------------------------------

// The Mahony attitude (SEEDS.md C.3) over a whole imu.csv, sampled at every IMU time.
struct AttitudeTrack {
  std::vector<TimeNs> t;
  std::vector<Eigen::Quaterniond> q;

  std::optional<Eigen::Matrix3d> at(TimeNs when) const {
    if (t.empty() || when < t.front() || when > t.back() + kNsPerSecond / 10) return std::nullopt;
    auto it = std::lower_bound(t.begin(), t.end(), when);
    if (it == t.end()) return q.back().toRotationMatrix();
    const std::size_t i = static_cast<std::size_t>(it - t.begin());
    if (i == 0) return q.front().toRotationMatrix();
    const double w = static_cast<double>(when - t[i - 1]) / static_cast<double>(t[i] - t[i - 1]);
    return q[i - 1].slerp(w, q[i]).toRotationMatrix();
  }
};

AttitudeTrack run_mahony(const fs::path& imu_csv) {
  ImuCsvSource src(imu_csv.string());
  MahonyFilter ahrs;
  AttitudeTrack track;
  SensorData d;
  while (src.next(d)) {
    const auto* s = std::get_if<ImuSample>(&d);
    if (!s) continue;
    ahrs.update(*s);
    if (!ahrs.initialized()) continue;
    track.t.push_back(s->t);
    track.q.push_back(ahrs.q_BtoW());
  }
  return track;
}

// ---- statistics ------------------------------------------------------------------------

// Decoded frequencies off the map's by more than this (median over the identified blobs):
// the report suggests the row time is wrong. Sub-row period estimates put the median within
// ~0.2 % on the simulated sessions.
constexpr double kRowTimeHintFraction = 0.005;

struct Running {
  long n = 0;
  double mean = 0, m2 = 0;
  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (x - mean);
  }
  double sd() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0; }
};

struct ErrorStats {
  std::vector<double> e;
  long attempts = 0;  // frames the method was tried on
  double quantile(double q) const {
    if (e.empty()) return std::nan("");
    std::vector<double> s = e;
    std::sort(s.begin(), s.end());
    const std::size_t k = std::min(s.size() - 1, static_cast<std::size_t>(std::ceil(q * static_cast<double>(s.size()))) -
                                                     (q > 0 ? 1 : 0));
    return s[k];
  }
};

void print_errors(const char* method, const ErrorStats& s, bool have_truth) {
  if (!have_truth) {
    std::fprintf(g_report, "  %-9s %ld fixes from %ld frames with LEDs\n", method, static_cast<long>(s.e.size()), s.attempts);
    return;
  }
  if (s.e.empty()) {
    std::fprintf(g_report, "  %-9s n 0 fixes (from %ld frames with LEDs)\n", method, s.attempts);
    return;
  }
  std::fprintf(g_report, "  %-9s n %ld fixes (from %ld frames with LEDs)  median %.3f m  p95 %.3f m  max %.3f m\n", method,
              static_cast<long>(s.e.size()), s.attempts, s.quantile(0.5), s.quantile(0.95), s.quantile(1.0));
}

// ---- live stop -------------------------------------------------------------------------

std::atomic<Source*> g_live{nullptr};
extern "C" void on_vlc_stop_signal(int) {
  if (Source* s = g_live.load()) s->request_stop();
}

// ---- the window ------------------------------------------------------------------------

class Viewer {
 public:
  explicit Viewer(bool wanted) {
    if (!wanted) return;
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    if ((!x || !*x) && (!w || !*w)) {
      std::fprintf(g_report, "--view: cannot open a window (neither DISPLAY nor WAYLAND_DISPLAY is set); carrying on without\n");
      return;
    }
    try {
      cv::namedWindow(kName, cv::WINDOW_AUTOSIZE);
      open_ = true;
    } catch (const cv::Exception& e) {
      std::fprintf(g_report, "--view: cannot open a window (%s); carrying on without\n", e.what());
    }
  }
  ~Viewer() {
    if (open_) cv::destroyWindow(kName);
  }
  bool open() const { return open_; }
  // False when the user closed the window or pressed q / Esc.
  bool show(const cv::Mat& gray, const std::vector<LedObservation>& obs, const std::string& caption) {
    if (!open_) return true;
    cv::Mat img;
    cv::cvtColor(gray, img, cv::COLOR_GRAY2BGR);
    for (const LedObservation& o : obs) {
      const cv::Point c(static_cast<int>(std::lround(o.uv.x())), static_cast<int>(std::lround(o.uv.y())));
      const cv::Scalar colour = o.classified() ? cv::Scalar(0, 220, 0) : cv::Scalar(0, 0, 255);
      cv::circle(img, c, std::max(3, static_cast<int>(o.radius_px)), colour, 1, cv::LINE_AA);
      char label[96];
      if (o.accepted())
        std::snprintf(label, sizeof label, "id %d %.0f Hz", o.led_id, o.freq_hz);
      else if (o.classified())
        std::snprintf(label, sizeof label, "class %d %.0f Hz", o.freq_class, o.freq_hz);
      else
        std::snprintf(label, sizeof label, "%s", o.reject_reason.c_str());
      cv::putText(img, label, c + cv::Point(8, -8), cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv::LINE_AA);
    }
    cv::putText(img, caption, {8, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 0), 1, cv::LINE_AA);
    try {
      cv::imshow(kName, img);
      const int key = cv::waitKey(1);
      if (key == 'q' || key == 27) return false;
      if (cv::getWindowProperty(kName, cv::WND_PROP_VISIBLE) < 1) return false;
    } catch (const cv::Exception&) {
      open_ = false;
    }
    return true;
  }

 private:
  static constexpr const char* kName = "luxloc vlc";
  bool open_ = false;
};

// ---- the run ---------------------------------------------------------------------------

int run_vlc(const VlcArgs& a) {
  if (a.playback.empty() == a.source.empty())
    throw InputError("--playback", 0, "--playback", "give either --playback DIR or --source v4l2:/dev/videoN");
  const bool want_geometry = a.position == "geometry" || a.position == "both";
  const bool want_rss = a.position == "rss" || a.position == "both";

  std::optional<LedMap> map;
  std::optional<CameraModel> camera;
  double device_height = a.device_height_m;
  SourcePtr frames;
  fs::path dir;
  SimTruth truth;
  AttitudeTrack attitude;
  bool have_truth = false;
  std::vector<std::pair<double, double>> blackouts;

  if (!a.playback.empty()) {
    dir = a.playback;
    PlaybackOptions po;
    if (!a.map_path.empty()) po.map_path = a.map_path;
    if (!a.camera_path.empty()) po.camera_path = a.camera_path;
    PlaybackSession session = open_playback(dir, po);
    map = session.map;
    camera = session.camera;
    if (!std::isfinite(device_height)) device_height = session.config.device_height_m;
    for (SourcePtr& s : session.sources)
      if (dynamic_cast<FrameListSource*>(s.get())) frames = std::move(s);
    if (!frames)
      throw InputError((dir / session.config.frames_file).string(), 0, "frames", "the session has no frames");
    if (session.groundtruth) {
      truth = read_truth(*session.groundtruth);
      have_truth = truth.rows.size() >= 2;
    }
    const fs::path imu = dir / session.config.imu_file;
    if ((want_geometry || want_rss) && !a.truth_attitude) {
      if (!fs::exists(imu))
        throw InputError(imu.string(), 0, "imu", "--position needs the IMU attitude (imu.csv), or --truth");
      attitude = run_mahony(imu);
    }
    if (a.check_ids) {
      if (!have_truth || !truth.has_tilt || !truth.has_z)
        throw InputError((dir / "groundtruth.csv").string(), 0, "roll",
                         "--check-ids needs the simulator's groundtruth.csv (t,x,y,z,yaw,roll,pitch)");
      blackouts = read_blackouts(dir / "sim_truth.yaml");
    }
    if (a.truth_attitude && !(have_truth && truth.has_tilt))
      throw InputError((dir / "groundtruth.csv").string(), 0, "roll", "--truth needs groundtruth.csv with yaw,roll,pitch");
  } else {
    if (a.map_path.empty() || a.camera_path.empty())
      throw InputError("--source", 0, "--map", "a live camera needs --map and --camera");
    if (a.check_ids || a.truth_attitude)
      throw InputError("--source", 0, "--check-ids", "--check-ids and --truth need a simulated --playback session");
    map = LedMap::load(a.map_path);
    camera = CameraModel::load(a.camera_path);
    const SourceSpec spec = SourceSpec::parse(a.source);
    if (spec.kind != "v4l2") throw InputError("--source", 0, "--source", "'" + a.source + "': vlc reads a v4l2 camera");
    frames = make_live_source(spec);
  }
  if (!map) throw InputError((dir / "ledmap.yaml").string(), 0, "leds", "no LED map (ledmap.yaml or --map)");
  if (!camera) throw InputError((dir / "camera.yaml").string(), 0, "camera_matrix", "no camera file (camera.yaml or --camera)");
  if ((want_geometry || want_rss) && !std::isfinite(device_height))
    std::fprintf(g_report, "note: no device_height_m (session.yaml or --height): geometry fixes need >= 2 LEDs, RSS none\n");

  const StripeDecoder decoder(*camera, *map);
  std::unique_ptr<TextFile> out;
  if (!a.out.empty()) {
    out = std::make_unique<TextFile>(a.out);
    if (out->is_stdout()) g_report = stderr;
    out->write("t,led_id,u,v,freq_hz,confidence,rows,border,reason\n");
  }
  Viewer viewer(a.view);
  if (frames->live()) {
    g_live.store(frames.get());
    std::signal(SIGINT, on_vlc_stop_signal);
    std::signal(SIGTERM, on_vlc_stop_signal);
    std::fprintf(g_report, "reading %s: Ctrl-C to stop\n", frames->name().c_str());
    std::fflush(g_report);
  }

  long n_frames = 0, n_with_leds = 0, n_blobs = 0, n_accepted = 0;
  std::map<int, Running> per_id;
  std::map<int, Running> per_class;  // decodes of reused frequencies (no LED named: issue 14)
  std::vector<double> freq_ratio;  // decoded / map frequency of every identified blob
  std::map<std::string, long> rejected;
  ErrorStats geo, rss;
  IdCheckCounts ids;
  std::mt19937_64 rng(1);
  sim::RenderOptions truth_render;
  truth_render.read_noise_dn = 0.0;
  truth_render.shot_noise = false;
  RssOptions rss_options;
  rss_options.C = a.rss_c;
  std::vector<RssSample> rss_training;
  bool rss_calibrated = !(a.rss_calibrate_s > 0);
  double t_first = std::nan("");
  double decode_seconds = 0.0;

  SensorData d;
  char line[256];
  while (frames->next(d)) {
    auto* f = std::get_if<FrameSample>(&d);
    if (!f || f->gray.empty()) continue;
    const double t = ns_to_seconds(f->t);
    if (std::isnan(t_first)) t_first = t;
    if (a.duration_s > 0 && t - t_first > a.duration_s) break;
    ++n_frames;
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<LedObservation> obs = decoder.decode(f->gray);
    decode_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    int accepted = 0, reused = 0;
    double rows = 0;
    for (const LedObservation& o : obs) {
      ++n_blobs;
      if (o.accepted()) {
        ++accepted;
        rows += o.uv.y();
        per_id[o.led_id].add(o.freq_hz);
        freq_ratio.push_back(o.freq_hz / map->leds()[static_cast<std::size_t>(o.led_index)].freq_hz);
      } else if (o.classified()) {  // a reused frequency: decoded, the copy is the filter's to tell
        ++reused;
        per_class[o.freq_class].add(o.freq_hz);
        freq_ratio.push_back(o.freq_hz / map->classes()[static_cast<std::size_t>(o.freq_class)].freq_hz);
      } else {
        rejected[o.reject_reason]++;
      }
      if (out) {
        std::snprintf(line, sizeof line, "%.6f,%d,%.2f,%.2f,%.1f,%.3f,%.1f,%d,%s\n", t, o.accepted() ? o.led_id : -1,
                      o.uv.x(), o.uv.y(), o.freq_hz, o.confidence, o.row_span, o.touches_border ? 1 : 0,
                      o.reject_reason.c_str());
        out->write(line);
      }
    }
    n_accepted += accepted + reused;
    if (accepted + reused > 0) ++n_with_leds;

    if (a.check_ids) {
      // The renderer's own truth for this frame, from the true pose at each row's time.
      bool dark = false;
      for (const auto& [s, dur] : blackouts) dark = dark || (t >= s && t < s + dur);
      std::vector<TrueLedBlob> tl;
      if (!dark) {
        tl = true_led_blobs(truth, *camera, *map, t, truth_render, rng);
      }
      tally_ids(obs, tl, ids);
    }

    // Single-frame positions at the observation time: mid-exposure of the decoded rows.
    std::snprintf(line, sizeof line, "t %.3f s, %d LEDs", t, accepted);
    std::string caption = line;
    if ((want_geometry || want_rss) && accepted > 0) {
      const double t_obs = t + camera->row_offset_s(rows / accepted) + 0.5 * camera->exposure_s;
      std::optional<Eigen::Matrix3d> R;
      Eigen::Matrix3d R_true;
      Eigen::Vector3d p_true;
      const bool truth_here = have_truth && truth.at(t_obs, R_true, p_true);
      if (a.truth_attitude)
        R = truth_here ? std::optional(R_true) : std::nullopt;
      else if (frames->live())
        R = Eigen::Matrix3d::Identity();  // no IMU on the live path: the device held level
      else
        R = attitude.at(seconds_to_ns(t_obs));
      if (R) {
        if (want_geometry) {
          ++geo.attempts;
          const VlcFix fix = bearing_fix(obs, *map, *camera, *R, device_height);
          if (fix.valid) {
            if (truth_here) geo.e.push_back((fix.p_BinW - p_true).head<2>().norm());
            else if (!have_truth) geo.e.push_back(0.0);
            std::snprintf(line, sizeof line, "  geometry (%.2f, %.2f)", fix.p_BinW.x(), fix.p_BinW.y());
            caption += line;
          }
        }
        if (want_rss && std::isfinite(device_height)) {
          const std::vector<RssMeasurement> m = rss_measurements_from(obs, *map, rss_options);
          const double z_rx = device_height + (*R * camera->p_CinB).z();
          if (!rss_calibrated) {
            if (t - t_first < a.rss_calibrate_s) {
              if (truth_here)
                for (const RssMeasurement& x : m) rss_training.push_back({x, p_true + R_true * camera->p_CinB});
            } else {
              const RssCalibration c = calibrate_rss_constant(rss_training);
              rss_calibrated = true;
              if (c.valid) rss_options.C = c.C;
              std::fprintf(g_report, "rss: channel constant C = %.4g from %d blobs of the first %.0f s against the truth (rms log "
                          "power %.3f, range %.3f m)%s\n",
                          c.C, c.samples, a.rss_calibrate_s, c.rms_log_residual, c.rms_range_error_m,
                          c.valid ? "" : ": not valid, C solved per frame");
            }
          }
          if (rss_calibrated) {
            ++rss.attempts;
            const VlcFix fix = rss_fix(m, z_rx, rss_options, *R, camera->p_CinB);
            if (fix.valid) {
              if (truth_here) rss.e.push_back((fix.p_BinW - p_true).head<2>().norm());
              else if (!have_truth) rss.e.push_back(0.0);
              std::snprintf(line, sizeof line, "  rss (%.2f, %.2f)", fix.p_BinW.x(), fix.p_BinW.y());
              caption += line;
            }
          }
        }
      }
    }
    if (!viewer.show(f->gray, obs, caption)) {
      frames->request_stop();
      break;
    }
  }
  g_live.store(nullptr);
  if (out) out->flush();

  // ---- the report ----
  std::fprintf(g_report, "frames %ld, frames with LEDs %ld (%.1f %%), blobs %ld, decoded %ld, rejected %ld\n", n_frames,
              n_with_leds, n_frames ? 100.0 * n_with_leds / n_frames : 0.0, n_blobs, n_accepted, n_blobs - n_accepted);
  if (n_frames > 0)
    std::fprintf(g_report, "decode time: %.2f ms per frame (mean, one thread, incl. every blob)\n",
                1e3 * decode_seconds / static_cast<double>(n_frames));
  // Every LED of the map, seen or not; "needs rows": the blob height below which the
  // decoder refuses it (min_periods stripe periods of its frequency): a room-design check.
  // A map that reuses frequencies (issue 14): a decode names a class, not an LED, so the
  // table is per class (its copies: how many LEDs share the frequency).
  if (map->reuses_frequencies()) {
    std::fprintf(g_report, "the map reuses frequencies: %zu LEDs in %zu classes, copies >= %.2f m apart\n", map->size(),
                 map->classes().size(), map->min_reuse_distance_m());
    std::fprintf(g_report, "decoded per frequency class:\n  %6s %6s %8s %10s %10s %9s %7s %8s %10s\n", "class", "copies",
                 "decodes", "map Hz", "mean Hz", "sd Hz", "sd %", "period", "needs rows");
    for (std::size_t k = 0; k < map->classes().size(); ++k) {
      const FrequencyClass& fc = map->classes()[k];
      Running r = per_class.count(static_cast<int>(k)) ? per_class.at(static_cast<int>(k)) : Running{};
      if (fc.members.size() == 1 && per_id.count(map->leds()[static_cast<std::size_t>(fc.members[0])].id))
        r = per_id.at(map->leds()[static_cast<std::size_t>(fc.members[0])].id);
      const double period = 1.0 / (fc.freq_hz * camera->row_time_s);
      const auto num = [](bool have, double v, int digits) {
        char b[32];
        std::snprintf(b, sizeof b, "%.*f", digits, v);
        return have ? std::string(b) : std::string("-");
      };
      std::fprintf(g_report, "  %6zu %6zu %8ld %10.1f %10s %9s %7s %8.1f %10.0f\n", k, fc.members.size(), r.n, fc.freq_hz,
                   num(r.n > 0, r.mean, 1).c_str(), num(r.n > 1, r.sd(), 1).c_str(),
                   num(r.n > 1 && r.mean > 0, r.mean > 0 ? 100.0 * r.sd() / r.mean : 0.0, 2).c_str(), period, std::ceil(decoder.options().min_periods * period));
    }
  } else {
  std::fprintf(g_report, "decoded per LED (map order):\n  %6s %8s %10s %10s %9s %7s %8s %10s\n", "id", "decodes", "map Hz",
              "mean Hz", "sd Hz", "sd %", "period", "needs rows");
  for (const Led& led : map->leds()) {
    const auto it = per_id.find(led.id);
    const Running r = it == per_id.end() ? Running{} : it->second;
    const double period = 1.0 / (led.freq_hz * camera->row_time_s);
    if (r.n > 0)
      std::fprintf(g_report, "  %6d %8ld %10.1f %10.1f %9.1f %7.2f %8.1f %10.0f\n", led.id, r.n, led.freq_hz, r.mean, r.sd(),
                  r.mean > 0 ? 100.0 * r.sd() / r.mean : 0.0, period, std::ceil(decoder.options().min_periods * period));
    else
      std::fprintf(g_report, "  %6d %8d %10.1f %10s %9s %7s %8.1f %10.0f\n", led.id, 0, led.freq_hz, "-", "-", "-", period,
                  std::ceil(decoder.options().min_periods * period));
  }
  }
  // A wrong row time scales every decoded frequency by the same factor (f = 1 / (period *
  // row_time)): the median ratio over the identified blobs shows it before the ids fail.
  if (freq_ratio.size() >= 20) {
    std::nth_element(freq_ratio.begin(), freq_ratio.begin() + static_cast<long>(freq_ratio.size() / 2), freq_ratio.end());
    const double ratio = freq_ratio[freq_ratio.size() / 2];
    std::fprintf(g_report, "frequency scale: decoded / map %.4f (median of %zu identified blobs)\n", ratio,
                 freq_ratio.size());
    if (std::abs(ratio - 1.0) > kRowTimeHintFraction)
      std::fprintf(g_report,
                   "  the LEDs read %.1f %% %s: camera.yaml's row_time_us %.3f%s is probably %.3f; measure it with "
                   "`luxloc calib rowtime` (or check the map's frequencies)\n",
                   100.0 * std::abs(ratio - 1.0), ratio > 1.0 ? "high" : "low", camera->row_time_s * 1e6,
                   camera->row_time_known ? "" : " (not in the file: a guess)", camera->row_time_s * ratio * 1e6);
  }
  if (!rejected.empty()) {
    std::fprintf(g_report, "rejected blobs by reason:\n");
    for (const auto& [why, n] : rejected) std::fprintf(g_report, "  %-22s %ld\n", why.c_str(), n);
  }
  if (want_geometry || want_rss) {
    std::fprintf(g_report, "single-frame positions (%s attitude%s):\n",
                a.truth_attitude ? "true" : frames->live() ? "level (no IMU)" : "IMU (Mahony)",
                have_truth ? "; horizontal error against groundtruth.csv" : "");
    if (want_geometry) print_errors("geometry", geo, have_truth);
    if (want_rss) print_errors("rss", rss, have_truth);
  }
  if (a.check_ids) {
    std::fprintf(g_report, "id check (renderer truth from groundtruth.csv, camera, map):\n");
    std::fprintf(g_report, "  blobs fully inside & >= 20 rows %ld: right %ld (%.2f %%), missed %ld\n", ids.qualifying, ids.right,
                100.0 * ids.right_fraction(), ids.missed);
    for (const auto& [why, n] : ids.missed_by) std::fprintf(g_report, "    missed: %-20s %ld\n", why.c_str(), n);
    for (const auto& [id, n] : ids.missed_by_id) std::fprintf(g_report, "    missed: LED %-16d %ld\n", id, n);
    std::fprintf(g_report, "  decodes %ld: wrong %ld (%.3f %% of all decodes)\n", ids.decodes, ids.wrong, 100.0 * ids.wrong_fraction());
    std::fprintf(g_report, "  dark frames %ld: LEDs decoded in them %ld\n", ids.dark_frames, ids.dark_frame_decodes);
  }
  for (const auto& [reason, e] : frames->drops().snapshot())
    std::fprintf(g_report, "frames skipped (%s): %llu; first: %s\n", reason.c_str(), static_cast<unsigned long long>(e.count),
                e.first_message.c_str());
  std::fflush(g_report);
  if (const std::string why = frames->failure(); !why.empty()) {
    std::fprintf(stderr, "luxloc: %s\n", why.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

void add_vlc_command(CLI::App& root, Action& action) {
  auto args = std::make_shared<VlcArgs>();
  CLI::App* cmd = root.add_subcommand(
      "vlc", "LED decode report for a session or a live camera: decodes per LED, rejects, positions, id accuracy");
  cmd->add_option("--playback", args->playback, "session folder (frames.csv, ledmap.yaml, camera.yaml)");
  cmd->add_option("--source", args->source, "live camera instead: v4l2:/dev/videoN[,width=..,exposure_us=..]");
  cmd->add_option("--map", args->map_path, "LED map (default: the session's ledmap.yaml)");
  cmd->add_option("--camera", args->camera_path, "camera file (default: the session's camera.yaml)");
  cmd->add_option("--out", args->out, "CSV, one row per blob: t,led_id,u,v,freq_hz,confidence,rows,border,reason (- = stdout; the report then goes to stderr)");
  cmd->add_flag("--view", args->view, "show the frames with the blobs, ids and positions (needs a display)");
  cmd->add_option("--position", args->position, "single-frame positions: geometry (bearing), rss, both, none")
      ->check(CLI::IsMember({"geometry", "rss", "both", "none"}))
      ->capture_default_str();
  cmd->add_flag("--truth", args->truth_attitude,
                "use the true attitude from groundtruth.csv instead of the IMU (isolates the VLC geometry)");
  cmd->add_flag("--check-ids", args->check_ids,
                "decoder id accuracy against the simulator's truth (re-rendered from groundtruth.csv)");
  cmd->add_option("--duration", args->duration_s, "stop after this many seconds of frames")->check(CLI::PositiveNumber);
  cmd->add_option("--height", args->device_height_m, "device height above the floor, m (default: session.yaml)");
  cmd->add_option("--rss-c", args->rss_c, "RSS channel constant C (default: solved per frame, needs >= 4 LEDs)");
  cmd->add_option("--rss-calibrate", args->rss_calibrate_s,
                  "fit C on the first S seconds against groundtruth.csv (a survey), then fix the rest")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([args, &action] { action = [args] { return run_vlc(*args); }; });
}

}  // namespace luxloc::app
