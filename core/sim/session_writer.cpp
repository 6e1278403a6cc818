#include "core/sim/session_writer.hpp"

#include "core/common/session_file.hpp"
#include "core/sim/seeding.hpp"

#include <atomic>
#include <cstdio>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <regex>
#include <stdexcept>
#include <string>
#include <tbb/parallel_for.h>

namespace luxloc::sim {
namespace {

namespace fs = std::filesystem;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File open_out(const fs::path& p) {
  File f(std::fopen(p.c_str(), "w"));
  if (!f) throw std::runtime_error("cannot write " + p.string());
  return f;
}

void close_checked(File f, const fs::path& p) {
  std::FILE* raw = f.release();
  if (std::ferror(raw) != 0 || std::fclose(raw) != 0) throw std::runtime_error("error writing " + p.string());
}

void write_imu(const Simulator& sim, const fs::path& p) {
  File f = open_out(p);
  std::fputs("t,ax,ay,az,gx,gy,gz,mx,my,mz\n", f.get());
  for (const ImuSample& s : sim.imu_samples())
    std::fprintf(f.get(), "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f\n", ns_to_seconds(s.t), s.acc_inB.x(),
                 s.acc_inB.y(), s.acc_inB.z(), s.gyro_inB.x(), s.gyro_inB.y(), s.gyro_inB.z(), s.mag_inB.x(),
                 s.mag_inB.y(), s.mag_inB.z());
  close_checked(std::move(f), p);
}

std::size_t write_truth(const Simulator& sim, const fs::path& p) {
  File f = open_out(p);
  std::fputs("t,x,y,z,yaw,roll,pitch\n", f.get());
  for (std::size_t k = 0; k < sim.imu_count(); ++k) {
    const BodyState s = sim.truth(sim.imu_time_s(k));
    std::fprintf(f.get(), "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", s.t, s.p_BinW.x(), s.p_BinW.y(), s.p_BinW.z(),
                 s.yaw, s.roll, s.pitch);
  }
  close_checked(std::move(f), p);
  return sim.imu_count();
}

std::size_t write_steps(const Simulator& sim, const fs::path& p) {
  File f = open_out(p);
  std::fputs("t,x,y\n", f.get());
  const std::vector<double> steps = sim.step_times();
  for (double t : steps) {
    const BodyState s = sim.truth(t);
    std::fprintf(f.get(), "%.6f,%.6f,%.6f\n", t, s.p_BinW.x(), s.p_BinW.y());
  }
  close_checked(std::move(f), p);
  return steps.size();
}

// Fixes on their own random stream, so adding them leaves every other file unchanged.
std::size_t write_fixes(const Simulator& sim, const fs::path& p, double rate_hz, double sigma_m) {
  File f = open_out(p);
  std::fputs("t,x,y,sigma_m\n", f.get());
  std::mt19937_64 rng = make_rng(sim.options().seed, RandomStream::fixes);
  std::normal_distribution<double> noise(0.0, sigma_m);
  std::size_t n = 0;
  for (double t = 0.5 / rate_hz; t < sim.duration_s(); t = static_cast<double>(++n) / rate_hz + 0.5 / rate_hz) {
    const BodyState s = sim.truth(t);
    const double ex = noise(rng), ey = noise(rng);
    std::fprintf(f.get(), "%.6f,%.6f,%.6f,%.4f\n", t, s.p_BinW.x() + ex, s.p_BinW.y() + ey, sigma_m);
  }
  close_checked(std::move(f), p);
  return n;
}

void write_session_yaml(const Simulator& sim, const fs::path& p) {
  SessionConfig c;
  c.device_height_m = sim.scenario().device_height_m;
  c.anchors = sim.scenario().anchors;
  save_session_config(c, p.string());  // the one writer of session.yaml (recorder, sim)
}

// uwb.csv (SPEC.md) plus the truth the filter must not see: nlos (0/1) and true_range_m
// (extra columns, ignored by playback).
std::size_t write_uwb(const Simulator& sim, const fs::path& p) {
  const std::vector<SimUwbMeasurement> ms = sim.uwb_measurements();
  File f = open_out(p);
  const bool aoa = sim.scenario().uwb.with_aoa;
  std::fputs(aoa ? "t,anchor,range_m,aoa_rad,nlos,true_range_m\n" : "t,anchor,range_m,nlos,true_range_m\n", f.get());
  for (const SimUwbMeasurement& m : ms) {
    if (aoa)
      std::fprintf(f.get(), "%.6f,%d,%.4f,%.5f,%d,%.4f\n", ns_to_seconds(m.sample.t), m.sample.anchor,
                   m.sample.range_m, m.sample.aoa_rad, m.nlos ? 1 : 0, m.true_range_m);
    else
      std::fprintf(f.get(), "%.6f,%d,%.4f,%d,%.4f\n", ns_to_seconds(m.sample.t), m.sample.anchor, m.sample.range_m,
                   m.nlos ? 1 : 0, m.true_range_m);
  }
  close_checked(std::move(f), p);
  return ms.size();
}

// What the simulator drew: handy to check calibrations and filters against.
void write_sim_truth(const Simulator& sim, const fs::path& p) {
  cv::FileStorage fs(p.string(), cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  if (!fs.isOpened()) throw std::runtime_error("cannot write " + p.string());
  const SimOptions& o = sim.options();
  const auto vec = [](const Eigen::Vector3d& v) { return cv::Mat(cv::Vec3d(v.x(), v.y(), v.z())); };
  fs << "scenario" << sim.scenario().name << "seed" << std::to_string(o.seed) << "duration_s" << sim.duration_s()
     << "fps" << o.fps << "imu_rate_hz" << o.imu_rate_hz << "frame_offset_s" << o.frame_offset_s;
  fs << "acc_bias_mps2" << vec(sim.imu_biases().acc) << "gyro_bias_rps" << vec(sim.imu_biases().gyro);
  fs << "acc_noise_mps2" << o.imu.acc_noise_mps2 << "gyro_noise_rps" << o.imu.gyro_noise_rps << "mag_noise_ut"
     << o.imu.mag_noise_ut << "mag_field_inW_ut" << vec(o.imu.mag_field_inW);
  // The IMU grades' extras, only when used: historic sessions keep their exact file.
  const ImuBiases& drawn = sim.imu_biases();
  if (o.imu.gyro_scale_sigma > 0.0 || o.imu.acc_scale_sigma > 0.0)
    fs << "gyro_scale" << vec(drawn.gyro_scale) << "acc_scale" << vec(drawn.acc_scale);
  if (o.imu.gyro_bias_rw_rps_sqrt_s > 0.0)
    fs << "gyro_bias_rw_rps_sqrt_s" << o.imu.gyro_bias_rw_rps_sqrt_s << "gyro_bias_end_rps"
       << vec(sim.gyro_bias_track().back());
  if (sim.magnetic_field().disturbed()) {
    fs << "mag_disturbance" << o.mag_disturbance << "steel" << "[";
    for (const SteelAnomaly& a : sim.magnetic_field().steel)
      fs << "{:" << "x" << a.centre_inW.x() << "y" << a.centre_inW.y() << "radius_m" << a.radius_m << "delta_ut"
         << vec(a.delta_ut) << "}";
    fs << "]" << "magnets" << "[";
    for (const MagnetPass& g : sim.magnetic_field().magnets)
      fs << "{:" << "t_peak_s" << g.t_peak_s << "sigma_s" << g.sigma_s << "delta_ut" << vec(g.delta_ut) << "}";
    fs << "]";
  }
  // Issue 16: the per-anchor range biases (only when drawn: historic files stay as they were).
  if (const std::vector<UwbAnchorBias> biases = sim.uwb_biases(); !biases.empty()) {
    fs << "uwb_anchor_biases" << "[";
    for (const UwbAnchorBias& b : biases) {
      fs << "{:" << "id" << b.anchor << "bias_m" << b.bias_m;
      if (b.scale != 1.0) fs << "scale" << b.scale;
      fs << "}";
    }
    fs << "]";
    const UwbSimOptions& u = sim.scenario().uwb;
    if (u.blocked_anchor != 0)
      fs << "uwb_blocked" << "{" << "anchor" << u.blocked_anchor << "from_s" << u.blocked_from_s << "to_s"
         << u.blocked_to_s << "}";
  }
  fs << "led_phases" << "[";
  for (std::size_t i = 0; i < sim.scenario().map.size(); ++i)
    fs << "{:" << "id" << sim.scenario().map.leds()[i].id << "phase_s" << sim.led_phases_s()[i] << "}";
  fs << "]";
  fs << "blackouts" << "[";
  for (const Blackout& b : o.blackouts) fs << "{:" << "start_s" << b.start_s << "duration_s" << b.duration_s << "}";
  fs << "]";
  if (o.walker) {
    const WalkerDraw& w = *o.walker;
    fs << "walker" << "{" << "step_length_m" << w.step_length_m << "step_hz" << w.step_hz << "speed_mps" << w.speed_mps
       << "corner_sigma_m" << w.corner_sigma_m << "speed_modulation" << w.speed_modulation << "bounce_m" << w.bounce_m
       << "sway_scale" << w.sway_scale << "walking" << "[";
    for (const WalkInterval& i : w.walking)
      fs << "{:" << "start_s" << i.start_s << "stop_s" << (std::isfinite(i.stop_s) ? i.stop_s : -1.0) << "}";
    fs << "]" << "pace_waves" << "[";
    for (const PaceWave& wave : w.pace_waves)
      fs << "{:" << "amplitude" << wave.amplitude << "period_s" << wave.period_s << "phase_rad" << wave.phase_rad << "}";
    fs << "]" << "turns" << "[";
    for (const TurnOnSpot& t : w.turns)
      fs << "{:" << "start_s" << t.start_s << "duration_s" << t.duration_s << "yaw_deg" << (t.left ? 180 : -180) << "}";
    fs << "]" << "side_steps" << "[";
    for (const SideStep& s : w.side_steps)
      fs << "{:" << "start_s" << s.start_s << "duration_s" << s.duration_s << "turn_s" << s.ramp_s << "direction"
         << (s.left ? "left" : "right") << "slowdown" << s.slowdown << "}";
    fs << "]" << "lever_arm_m" << "[:" << w.lever_arm_m.x() << w.lever_arm_m.y() << "]" << "}";
  }
  if (o.world_plan) {
    const WorldPlan& w = *o.world_plan;
    const CameraModel& c = sim.scenario().camera;
    fs << "world" << "{" << "kind" << (o.world ? "random" : "camera-mode") << "width" << c.width << "height" << c.height
       << "row_time_us" << c.row_time_s * 1e6 << "exposure_us" << c.exposure_s * 1e6;
    if (o.world) fs << "exposure_drawn_us" << o.world->camera.exposure_s * 1e6;
    const CameraMode& m = o.world ? o.world->camera : *o.camera_mode;
    fs << "hfov_deg" << m.hfov_deg << "fx_px" << c.fx << "k1" << c.dist[0];
    if (o.world)
      fs << "layout" << o.world->layout << "spacing_m" << o.world->spacing_m << "ceiling_m" << o.world->ceiling_m
         << "led_diameter_drawn_m" << o.world->led_diameter_m;
    fs << "led_diameter_m" << w.led_diameter_m << "leds" << w.leds << "classes" << w.classes << "band_hz" << "[:"
       << w.band.f_min_hz << w.band.f_max_hz << "]" << "band_limit" << w.band.high_limit << "min_reuse_distance_m"
       << (std::isfinite(w.min_reuse_distance_m) ? w.min_reuse_distance_m : -1.0) << "}";
  }
  if (o.heel_impact_mps2 > 0.0)
    fs << "heel_impact" << "{" << "peak_mps2" << o.heel_impact_mps2 << "width_s" << GaitOptions{}.heel_impact_width_s
       << "}";
  if (o.kidnap) {
    const SimOptions::Kidnap& k = *o.kidnap;
    fs << "kidnap" << "{" << "start_s" << k.start_s << "end_s" << k.end_s << "from" << "[:" << k.from.x() << k.from.y()
       << "]" << "to" << "[:" << k.to.x() << k.to.y() << "]" << "}";
  }
  fs << "peak_dn" << o.render.peak_dn << "black_dn" << o.render.black_dn << "read_noise_dn" << o.render.read_noise_dn;
}

void remove_stale_frames(const fs::path& frames_dir) {
  static const std::regex frame_name(R"(\d{6}\.(png|jpg))");
  if (!fs::is_directory(frames_dir)) return;
  std::vector<fs::path> stale;
  for (const fs::directory_entry& e : fs::directory_iterator(frames_dir))
    if (e.is_regular_file() && std::regex_match(e.path().filename().string(), frame_name)) stale.push_back(e.path());
  for (const fs::path& p : stale) fs::remove(p);
}

std::size_t write_frames(const Simulator& sim, const fs::path& dir, const SessionWriteOptions& o,
                         std::uintmax_t& frame_bytes) {
  const fs::path frames_dir = dir / "frames";
  remove_stale_frames(frames_dir);
  fs::create_directories(frames_dir);
  const std::size_t n = sim.frame_count();
  const char* ext = o.format == ImageFormat::png ? "png" : "jpg";
  const auto name = [ext](std::size_t k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "frames/%06zu.%s", k, ext);
    return std::string(buf);
  };
  File f = open_out(dir / "frames.csv");
  std::fputs("t,file\n", f.get());
  for (std::size_t k = 0; k < n; ++k) std::fprintf(f.get(), "%.6f,%s\n", sim.frame_time_s(k), name(k).c_str());
  close_checked(std::move(f), dir / "frames.csv");

  // Sensor noise defeats deflate's string matching: Huffman-only coding is then ~20 % smaller
  // and faster; an (almost) noise-free background still compresses best with the default.
  const int png_strategy = sim.options().render.read_noise_dn >= 0.3 ? cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY
                                                                     : cv::IMWRITE_PNG_STRATEGY_DEFAULT;
  const std::vector<int> params =
      o.format == ImageFormat::png
          ? std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, o.png_compression, cv::IMWRITE_PNG_STRATEGY, png_strategy}
          : std::vector<int>{cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality};
  std::atomic<bool> failed{false};
  std::atomic<std::uintmax_t> bytes{0};
  // Each frame's noise comes from its own (seed, index) stream: parallel order is irrelevant.
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    if (failed.load()) return;
    const RenderedFrame frame = sim.render(k);
    std::vector<uchar> buf;
    if (!cv::imencode(o.format == ImageFormat::png ? ".png" : ".jpg", frame.gray, buf, params)) {
      failed = true;
      return;
    }
    File out(std::fopen((dir / name(k)).c_str(), "wb"));
    if (!out || std::fwrite(buf.data(), 1, buf.size(), out.get()) != buf.size() || std::fclose(out.release()) != 0) {
      failed = true;
      return;
    }
    bytes += buf.size();
  });
  if (failed) throw std::runtime_error("cannot write frames under " + frames_dir.string());
  frame_bytes = bytes;
  return n;
}

}  // namespace

SessionSummary write_session(const Simulator& sim, const fs::path& dir, const SessionWriteOptions& options) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw std::runtime_error("cannot create session folder " + dir.string());
  SessionSummary s;
  write_imu(sim, dir / "imu.csv");
  s.imu_samples = sim.imu_count();
  s.truth_rows = write_truth(sim, dir / "groundtruth.csv");
  s.steps = write_steps(sim, dir / "steps.csv");
  if (!sim.scenario().map.empty()) sim.scenario().map.save((dir / "ledmap.yaml").string());
  else fs::remove(dir / "ledmap.yaml", ec);  // no stale map from an earlier run
  if (sim.scenario().start_fix) {  // relative navigation starts from a known point
    const BodyState s0 = sim.truth(0.0);
    File f = open_out(dir / "fixes.csv");
    std::fprintf(f.get(), "t,x,y,sigma_m\n%.6f,%.6f,%.6f,0.02\n", 0.0, s0.p_BinW.x(), s0.p_BinW.y());
    close_checked(std::move(f), dir / "fixes.csv");
  }
  sim.scenario().camera.save((dir / "camera.yaml").string());
  write_session_yaml(sim, dir / "session.yaml");
  write_sim_truth(sim, dir / "sim_truth.yaml");
  s.files = sim.scenario().start_fix ? 8 : 7;
  if (options.fixes_rate_hz > 0.0) {
    if (!(options.fixes_sigma_m > 0.0)) throw std::invalid_argument("fixes_sigma_m must be > 0");
    s.fixes = write_fixes(sim, dir / "fixes.csv", options.fixes_rate_hz, options.fixes_sigma_m);
    ++s.files;
  } else if (!sim.scenario().start_fix) {  // the start fix written above stays
    fs::remove(dir / "fixes.csv", ec);
  }
  if (!sim.scenario().anchors.empty()) {
    s.uwb_rows = write_uwb(sim, dir / "uwb.csv");
    s.files += 1;
  } else {  // no stale uwb.csv from an earlier run may remain
    fs::remove(dir / "uwb.csv", ec);
  }
  if (options.write_frames && sim.scenario().frames) {
    s.frames = write_frames(sim, dir, options, s.frame_bytes);
    s.files += 1 + s.frames;
  } else {  // an IMU-only session: no stale frames from an earlier run may remain
    remove_stale_frames(dir / "frames");
    fs::remove(dir / "frames.csv", ec);
  }
  for (const char* name : {"imu.csv", "groundtruth.csv", "steps.csv", "ledmap.yaml", "camera.yaml", "session.yaml",
                           "sim_truth.yaml", "frames.csv", "fixes.csv", "uwb.csv"})
    if (fs::exists(dir / name)) s.bytes += fs::file_size(dir / name);
  s.bytes += s.frame_bytes;
  return s;
}

}  // namespace luxloc::sim
