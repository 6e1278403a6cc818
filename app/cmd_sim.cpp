// `luxloc sim`: writes a synthetic session folder (SPEC.md "Session folder"): rolling-shutter
// frames, IMU, ground truth, steps, LED map and camera. Model: docs/SIMULATOR.md.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "app/commands.hpp"
#include "core/common/input_error.hpp"
#include "core/sim/kidnap_trajectory.hpp"
#include "core/sim/imu_grade.hpp"
#include "core/sim/mag_disturbance.hpp"
#include "core/sim/walker_population.hpp"
#include "core/sim/world_population.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/session_writer.hpp"
#include "core/sim/simulator.hpp"

namespace luxloc::app {
namespace {

struct SimArgs {
  std::string out;
  std::string scenario = "walk";
  std::uint64_t seed = 1;
  double duration_s = 0.0;
  double fps = 30.0;
  std::vector<std::string> blackouts;
  std::string kidnap;  // START:DISTANCE
  bool no_frames = false;
  bool camera = false;  // frames in a scenario that has no camera (drone, robot)
  std::string frame_format = "jpg";
  std::string fixes;  // RATE_HZ:SIGMA_M
  int png_level = 1;
  int jpeg_quality = 95;
  double read_noise_dn = sim::RenderOptions{}.read_noise_dn;
  // IMU model (empty / unset: the scenario's).
  std::string imu_grade;
  std::string mag_disturbance;
  std::string walker = "default";
  std::string world = "default";  // --world random: a drawn camera mode and LED layout
  std::string camera_mode;        // --camera-mode WxH:ROW_US:EXPOSURE_US[:HFOV_DEG]
  double heel_impact_g = 0.0;  // --heel-impact: each heel strike's spike, g
  std::string gyro_bias_dps;  // "B" or "BX,BY,BZ": a fixed gyro bias
  std::optional<double> gyro_bias_rw_dps;
  std::optional<double> acc_bias_mps2;
  std::optional<double> scale_error;
  std::optional<double> uwb_scale_sigma;  // per-anchor UWB range scale error (sigma, fraction)
};

// "B" (every axis) or "BX,BY,BZ" in deg/s -> rad/s.
Eigen::Vector3d parse_gyro_bias(const std::string& text) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string item;
  try {
    while (std::getline(in, item, ',')) {
      std::size_t used = 0;
      const double x = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(x) || std::abs(x) > 100.0) throw std::invalid_argument(item);
      v.push_back(x * std::numbers::pi / 180.0);
    }
  } catch (const std::exception&) {
    v.clear();
  }
  if (v.size() == 1) return Eigen::Vector3d::Constant(v[0]);
  if (v.size() == 3) return {v[0], v[1], v[2]};
  throw CLI::ValidationError("--gyro-bias-dps", "expected B or BX,BY,BZ in deg/s (|B| <= 100), got '" + text + "'");
}

// "A:B": two finite numbers; `option` and `form` ("START:DURATION") name them in messages.
std::pair<double, double> parse_number_pair(const std::string& text, const char* option, const char* form) {
  const std::size_t colon = text.find(':');
  try {
    std::size_t used_a = 0, used_b = 0;
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
    const double va = std::stod(a, &used_a), vb = std::stod(b, &used_b);
    if (used_a != a.size() || used_b != b.size() || !std::isfinite(va) || !std::isfinite(vb))
      throw std::invalid_argument("trailing characters");
    return {va, vb};
  } catch (const std::exception&) {
    throw CLI::ValidationError(option, std::string("expected ") + form + ", got '" + text + "'");
  }
}

// "START:DURATION" in seconds, START >= 0, DURATION > 0.
sim::Blackout parse_blackout(const std::string& text) {
  sim::Blackout b;
  std::tie(b.start_s, b.duration_s) = parse_number_pair(text, "--blackout", "START:DURATION in seconds");
  if (b.start_s < 0.0 || !(b.duration_s > 0.0))
    throw CLI::ValidationError("--blackout", "START must be >= 0 and DURATION > 0 in '" + text + "'");
  return b;
}

// "RATE_HZ:SIGMA_M", both > 0.
std::pair<double, double> parse_fixes(const std::string& text) {
  const auto [rate, sigma] = parse_number_pair(text, "--fixes", "RATE_HZ:SIGMA_M");
  if (!(rate > 0.0) || !(sigma > 0.0))
    throw CLI::ValidationError("--fixes", "RATE_HZ and SIGMA_M must be > 0 in '" + text + "'");
  return {rate, sigma};
}

sim::KidnapOptions parse_kidnap(const std::string& text) {
  sim::KidnapOptions k;
  std::tie(k.start_s, k.distance_m) = parse_number_pair(text, "--kidnap", "START:DISTANCE (s, m)");
  if (!(k.start_s >= 0.0) || !(k.distance_m > 0.0))
    throw CLI::ValidationError("--kidnap", "START must be >= 0 and DISTANCE > 0 in '" + text + "'");
  return k;
}

int run_sim(const SimArgs& a) {
  const auto t_start = std::chrono::steady_clock::now();
  sim::SimOptions options;
  options.seed = a.seed;
  options.duration_s = a.duration_s;
  options.fps = a.fps;
  options.render.read_noise_dn = a.read_noise_dn;
  for (const std::string& b : a.blackouts) options.blackouts.push_back(parse_blackout(b));
  sim::Scenario scenario = sim::make_scenario(a.scenario);
  if (a.walker != "default" || a.heel_impact_g > 0.0) {
    const char* option = a.walker != "default" ? "--walker" : "--heel-impact";
    if (!scenario.walk)
      throw InputError(option, 0, option, "scenario '" + a.scenario + "' has no walker to replace");
    const double duration = a.duration_s > 0.0 ? a.duration_s : scenario.duration_s;
    sim::WalkOptions walk = *scenario.walk;
    if (a.walker != "default") {
      options.walker = a.walker == "fast"     ? sim::draw_fast_walker(a.seed, duration)
                       : a.walker == "steady"  ? sim::draw_steady_walker(a.seed, duration)
                       : a.walker == "turning" ? sim::draw_turning_walker(a.seed, duration)
                                               : sim::draw_walker(a.seed, duration);
      walk = sim::apply_walker(walk, *options.walker);
    }
    walk.gait.heel_impact_mps2 = options.heel_impact_mps2 = a.heel_impact_g * sim::kGravity;
    scenario.trajectory = std::make_shared<sim::WalkTrajectory>(walk);
  }
  if (!a.kidnap.empty()) {
    // The carry covers the camera: a blackout from the pick-up to the put-down.
    try {
      const auto k = std::make_shared<sim::KidnapTrajectory>(scenario.trajectory, parse_kidnap(a.kidnap));
      options.blackouts.push_back({k->start_s(), k->end_s() - k->start_s()});
      options.kidnap = sim::SimOptions::Kidnap{k->start_s(), k->end_s(), k->pick_up().p_BinW, k->put_down().p_BinW};
      scenario.trajectory = k;
    } catch (const std::invalid_argument& e) {
      throw InputError("--kidnap", 0, "--kidnap", e.what());
    }
  }
  options.imu = sim::imu_grade(a.imu_grade.empty() ? scenario.imu_grade : a.imu_grade);
  options.mag_disturbance = a.mag_disturbance.empty() ? scenario.mag_disturbance : a.mag_disturbance;
  if (!a.gyro_bias_dps.empty()) {
    options.imu.gyro_bias_fixed = true;
    options.imu.gyro_bias_fixed_rps = parse_gyro_bias(a.gyro_bias_dps);
  }
  if (a.gyro_bias_rw_dps) options.imu.gyro_bias_rw_rps_sqrt_s = *a.gyro_bias_rw_dps * std::numbers::pi / 180.0;
  if (a.acc_bias_mps2) options.imu.acc_bias_sigma_mps2 = *a.acc_bias_mps2;
  if (a.scale_error) options.imu.gyro_scale_sigma = options.imu.acc_scale_sigma = *a.scale_error;
  if (a.uwb_scale_sigma) {
    if (scenario.anchors.empty())
      throw InputError("--uwb-scale", 0, "--uwb-scale", "scenario '" + a.scenario + "' has no UWB anchors");
    scenario.uwb.scale_sigma = *a.uwb_scale_sigma;
  }
  if (a.camera) {
    if (a.no_frames) throw InputError("--camera", 0, "--camera", "--camera and --no-frames contradict each other");
    scenario.frames = true;  // the scenario's camera (the up-looking webcam) under its LED map
  }
  if (a.world != "default" || !a.camera_mode.empty()) {
    const char* option = a.world != "default" ? "--world" : "--camera-mode";
    if (a.world != "default" && !a.camera_mode.empty())
      throw InputError("--world", 0, "--world", "--world random draws its own camera: leave out --camera-mode");
    try {
      if (a.world != "default") {
        options.world = sim::draw_world(a.seed, a.fps);
        options.world_plan = sim::apply_world(scenario, *options.world, a.seed);
      } else {
        options.camera_mode = sim::parse_camera_mode(a.camera_mode);
        options.world_plan = sim::apply_camera_mode(scenario, *options.camera_mode, a.seed);
      }
    } catch (const std::invalid_argument& e) {
      throw InputError(option, 0, option, e.what());
    }
  }
  const sim::Simulator simulator(std::move(scenario), options);

  sim::SessionWriteOptions write;
  write.write_frames = !a.no_frames;
  write.format = a.frame_format == "png" ? sim::ImageFormat::png : sim::ImageFormat::jpeg;
  write.png_compression = a.png_level;
  write.jpeg_quality = a.jpeg_quality;
  if (!a.fixes.empty()) std::tie(write.fixes_rate_hz, write.fixes_sigma_m) = parse_fixes(a.fixes);
  const sim::SessionSummary s = sim::write_session(simulator, a.out, write);

  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  std::printf("sim %s: %.1f s, %zu frames%s, %zu IMU samples, %zu steps, %zu LEDs, %zu files (%.1f MB) -> %s in %.1f s\n",
              a.scenario.c_str(), simulator.duration_s(), s.frames,
              s.frames == 0 ? "" : (a.frame_format == "png" ? " (PNG)" : " (JPEG)"), s.imu_samples, s.steps,
              simulator.scenario().map.size(), s.files, static_cast<double>(s.bytes) / 1e6, a.out.c_str(), took);
  if (const auto& w = simulator.options().world_plan) {
    const CameraModel& c = simulator.scenario().camera;
    std::printf("  camera %dx%d, %.1f us rows, %.0f us exposure, f %.0f px; %d LEDs (%.2f m discs) in %d frequency "
                "classes over %.0f-%.0f Hz (sim_truth.yaml: world)\n",
                c.width, c.height, c.row_time_s * 1e6, c.exposure_s * 1e6, c.fx, w->leds, w->led_diameter_m,
                w->classes, w->band.f_min_hz, w->band.f_max_hz);
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

void add_sim_command(CLI::App& root, Action& action) {
  auto args = std::make_shared<SimArgs>();
  CLI::App* cmd = root.add_subcommand(
      "sim", "write a synthetic session folder: rolling-shutter frames, IMU, ground truth (docs/SIMULATOR.md)");
  cmd->add_option("--out", args->out, "session folder to write (created if needed)")->required();
  cmd->add_option("--scenario", args->scenario, "scenario")
      ->check(CLI::IsMember(sim::scenario_names()))
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "random seed (same seed -> identical files)")->capture_default_str();
  cmd->add_option("--duration", args->duration_s, "seconds to simulate (default: the scenario's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--fps", args->fps, "camera frame rate")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--blackout", args->blackouts, "START:DURATION seconds with all lights off (repeatable)")
      ->each([](const std::string& s) { (void)parse_blackout(s); });
  cmd->add_option("--kidnap", args->kidnap,
                  "at START s pick the device up, cover the camera and carry it (no steps, 1 m/s) to where its walk "
                  "is DISTANCE m away, then walk on from there (issue 14: global relocalisation)")
      ->type_name("START:DISTANCE")
      ->each([](const std::string& s) { (void)parse_kidnap(s); });
  cmd->add_flag("--no-frames", args->no_frames, "write no frames (IMU and truth only)");
  cmd->add_flag("--camera", args->camera,
                "render frames in a scenario without a camera too (drone, robot): the up-looking webcam under the "
                "4 x 3 LED grid, its height following the platform (issue 16: camera-geometry height)");
  cmd->add_option("--fixes", args->fixes,
                  "also write fixes.csv: absolute fixes at RATE_HZ from the truth plus SIGMA_M Gaussian noise per axis")
      ->type_name("RATE_HZ:SIGMA_M")
      ->each([](const std::string& s) { (void)parse_fixes(s); });
  // JPEG by default: like a webcam's MJPEG stream, and a 640x480 frame decodes in ~0.8 ms
  // against ~3.3 ms for a lossless PNG of the same noisy image (README "Measured figures").
  cmd->add_option("--frame-format", args->frame_format, "image files: jpg (quality --jpeg-quality) or png (lossless)")
      ->check(CLI::IsMember({"jpg", "png"}))
      ->capture_default_str();
  cmd->add_option("--jpeg-quality", args->jpeg_quality, "JPEG quality")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--png-level", args->png_level, "PNG zlib compression level")
      ->check(CLI::Range(0, 9))
      ->capture_default_str();
  cmd->add_option("--read-noise", args->read_noise_dn, "sensor read noise, DN (1 sigma)")
      ->check(CLI::Range(0.0, 50.0))
      ->capture_default_str();
  cmd->add_option("--imu-grade", args->imu_grade,
                  "IMU model: default (the historic sim IMU), ideal, tactical, consumer (gyro bias up to 1 deg/s, "
                  "bias walk, scale errors), poor (docs/SIMULATOR.md)")
      ->check(CLI::IsMember(sim::imu_grade_names()));
  cmd->add_option("--walker", args->walker,
                  "the pedestrian: default (the scenario's), random (drawn from --seed: step length 0.35-0.85 m, "
                  "cadence 1.4-2.2 Hz, turns, bounce, sway, stops of 1-10 s, the pace drifting by up to +-24 %, "
                  "turns round on the spot at some stops, side steps in half the walks, the device held up to "
                  "0.4 m off the body's turning axis), turning (the same draw without side steps, the device on "
                  "the axis), steady (turning at its drawn pace, no turns on the spot) or fast (the steady draw "
                  "at 1.7 m/s, 1.9-2.2 Hz); written to sim_truth.yaml")
      ->check(CLI::IsMember(std::vector<std::string>(std::begin(sim::kWalkerNames), std::end(sim::kWalkerNames))))
      ->capture_default_str();
  cmd->add_option("--world", args->world,
                  "the camera and the ceiling: default (the scenario's) or random (drawn from --seed: 640x480 to "
                  "1920x1080, 15-45 us rows, 50-300 us exposure, 50-95 deg lenses; LEDs on a grid or irregular, "
                  "2-4 m apart, 2.4-4 m ceilings; frequencies planned for that camera); written to sim_truth.yaml")
      ->check(CLI::IsMember(std::vector<std::string>(std::begin(sim::kWorldNames), std::end(sim::kWorldNames))))
      ->capture_default_str();
  cmd->add_option("--camera-mode", args->camera_mode,
                  "film with this camera mode (e.g. 1280x720:45:200:70, a 720p webcam reading a row in 45 us, "
                  "200 us exposure, 70 deg lens; default lens 69.6 deg); the LED map's frequencies are planned "
                  "for it")
      ->type_name("WxH:ROW_US:EXPOSURE_US[:HFOV_DEG]")
      ->each([](const std::string& s) {
        try {
          (void)sim::parse_camera_mode(s);
        } catch (const std::invalid_argument& e) {
          throw CLI::ValidationError("--camera-mode", e.what());
        }
      });
  cmd->add_option("--heel-impact", args->heel_impact_g,
                  "each heel strike adds a vertical acceleration spike this high, in g (a device on the leg, in a "
                  "pocket or on the hip; ~50 ms, zero net velocity: 11 gives the accelerometer ~12 g peaks); 0: none")
      ->check(CLI::Range(0.0, 14.0))
      ->type_name("G");
  cmd->add_option("--mag-disturbance", args->mag_disturbance,
                  "magnetic disturbance: none, steel (a pillar beside the path at 30 % of the run), magnet (carried "
                  "past at 60 %), both")
      ->check(CLI::IsMember(sim::mag_disturbance_names()));
  cmd->add_option("--gyro-bias-dps", args->gyro_bias_dps, "fixed gyro bias instead of the grade's draw: B or BX,BY,BZ")
      ->each([](const std::string& s) { (void)parse_gyro_bias(s); });
  cmd->add_option("--gyro-bias-rw", args->gyro_bias_rw_dps, "gyro bias random walk, deg/s per sqrt(s)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--acc-bias", args->acc_bias_mps2, "accelerometer bias sigma per axis, m/s^2")
      ->check(CLI::Range(0.0, 2.0));
  cmd->add_option("--uwb-scale", args->uwb_scale_sigma,
                  "per-anchor UWB range scale error: measured = scale * true + bias, scale = 1 + N(0, SIGMA) per anchor "
                  "(fraction; scenarios with anchors; written to sim_truth.yaml)")
      ->check(CLI::Range(0.0, 0.1));
  cmd->add_option("--scale-error", args->scale_error, "gyro and accelerometer scale-error sigma per axis (fraction)")
      ->check(CLI::Range(0.0, 0.2));
  cmd->callback([args, &action] { action = [args] { return run_sim(*args); }; });
}

}  // namespace luxloc::app
