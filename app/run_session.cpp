#include "app/run_session.hpp"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <memory>
#include <optional>
#include <ostream>
#include <tbb/global_control.h>

#include "core/common/input_error.hpp"
#include "core/filter/filter_factory.hpp"
#include "core/filter/motion_model.hpp"
#include "core/imu/imu_calibration.hpp"
#include "core/vlc/camera_model.hpp"
#include "plugins/output/pose_file_sinks.hpp"
#include "plugins/output/status_line.hpp"
#include "plugins/output/mqtt_pose_sink.hpp"
#include "plugins/output/udp_pose_sink.hpp"
#include "plugins/web/live_view_sink.hpp"
#include "core/pipeline/counting_stage.hpp"
#include <unistd.h>
#include <cstdio>
#include "plugins/playback/playback_session.hpp"
#include "plugins/record/session_recorder.hpp"
#include "core/vlc/led_visibility.hpp"
#include "core/pipeline/tee_stage.hpp"
#include "plugins/external/external_plugin.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc::app {
namespace {

std::atomic<Pipeline*> g_running{nullptr};

extern "C" void on_stop_signal(int) {
  if (Pipeline* p = g_running.load()) p->stop();  // an atomic store: async-signal-safe
}

// Installs the handlers for the lifetime of a run and restores the old ones after.
class StopSignals {
 public:
  explicit StopSignals(Pipeline& p) {
    g_running.store(&p);
    old_int_ = std::signal(SIGINT, on_stop_signal);
    old_term_ = std::signal(SIGTERM, on_stop_signal);
  }
  ~StopSignals() {
    std::signal(SIGINT, old_int_);
    std::signal(SIGTERM, old_term_);
    g_running.store(nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  void (*old_int_)(int) = SIG_DFL;
  void (*old_term_)(int) = SIG_DFL;
};

double parse_seconds(const std::string& s, const std::string& what) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw InputError("--clock-offset", 0, "--clock-offset", "'" + what + "': '" + s + "' is not a number of seconds");
  }
}

}  // namespace

void add_run_options(CLI::App* sub, RunConfig& cfg) {
  std::string kinds = "playback";
  for (const auto& k : live_source_kinds()) kinds += ", " + k;
  sub->add_option("--source", cfg.sources, "sensor source KIND:TARGET[,key=value...] (repeatable); kinds: " + kinds)
      ->type_name("SPEC");
  sub->add_option("--playback", cfg.playback, "play back a session folder (SPEC.md layout)")->type_name("DIR");
  sub->add_option("--plugin", cfg.plugins, "load an external source plugin (C ABI, plugins/abi/luxloc_plugin.h); repeatable")
      ->type_name("PATH.so");
  sub->add_option("--map", cfg.map, "LED map (default: the session's ledmap.yaml)")->type_name("FILE");
  sub->add_option("--camera", cfg.camera, "camera file (default: the session's camera.yaml)")->type_name("FILE");
  sub->add_option("--filter", cfg.fusion.filter, "fusion filter (pf = seed A's SIR particle filter)")
      ->check(CLI::IsMember(filter_names()))
      ->capture_default_str();
  sub->add_option("--particles", cfg.fusion.pf.particles, "number of particles")
      ->check(CLI::Range(10, 10'000'000))
      ->capture_default_str();
  sub->add_option("--coupling", cfg.coupling,
                  "VLC coupling: tight (weigh particles by each LED's reprojection error) | loose (seed A: "
                  "one position fix per frame)")
      ->check(CLI::IsMember({"tight", "loose"}))
      ->capture_default_str();
  sub->add_option("--motion", cfg.motion,
                  "motion model of the prediction: pdr (steps, step length, attitude heading; gait calibrated by "
                  "the fixes) | strapdown (world acceleration) | cv (constant velocity, no IMU) | auto (pdr whose steps count only "
                  "once a gait is seen: cadence 1.2-2.5 Hz, regular, alike; strapdown until then, so vibration "
                  "cannot walk away; strapdown with --vo: a vehicle, seed C; --platform decides when given); "
                  "docs/MOTION.md")
      ->check(CLI::IsMember([] {
        auto names = motion_model_names();
        names.push_back("auto");
        return names;
      }()))
      ->capture_default_str();
  sub->add_option("--platform", cfg.platform,
                  "what carries the device, when known: pedestrian | handheld (pdr) | robot | vehicle (cv: smooth, "
                  "no gait) | drone (strapdown); sets the motion model of --motion auto")
      ->check(CLI::IsMember({"pedestrian", "handheld", "robot", "vehicle", "drone"}));
  sub->add_option("--imu-calib", cfg.imu_calib, "IMU calibration YAML from `luxloc calib imu`")
      ->check(CLI::ExistingFile)
      ->type_name("FILE");
  sub->add_option("--resampling", cfg.resampling, "systematic | stratified | multinomial | residual")
      ->check(CLI::IsMember({"systematic", "stratified", "multinomial", "residual"}))
      ->capture_default_str();
  sub->add_option("--resample-threshold", cfg.fusion.pf.resample_threshold,
                  "resample when n_eff < threshold * N")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  sub->add_flag("--resample-every-fix", cfg.fusion.pf.resample_every_correction,
                "resample after every correction (seed A, S303)");
  sub->add_option("--seed", cfg.fusion.pf.seed, "random seed (runs are deterministic for a seed)")
      ->capture_default_str();
  sub->add_option("--device-height", cfg.fusion.device_height_m,
                  "device height above the floor, m (default: session.yaml's device_height_m, else 1.0)");
  sub->add_option("--out", cfg.out, "pose file ('-' = stdout; default stdout when no --udp)")->type_name("FILE");
  sub->add_option("--format", cfg.format, "pose file format: csv | tum")
      ->check(CLI::IsMember({"csv", "tum"}))
      ->capture_default_str();
  sub->add_option("--udp", cfg.udp, "stream poses as JSON datagrams to HOST:PORT (repeatable)")
      ->type_name("HOST:PORT");
  sub->add_option("--mqtt", cfg.mqtt,
                  "publish poses as JSON to an MQTT broker, on TOPIC (default luxloc/<device-id>/pose), status "
                  "once a second on luxloc/<device-id>/status (repeatable)")
      ->type_name("HOST:PORT[/TOPIC]");
  sub->add_option("--device-id", cfg.device_id, "this device's id in the MQTT topics and messages (default: the host name)")
      ->type_name("ID");
  sub->add_option("--mqtt-tls-ca", cfg.mqtt_tls_ca, "MQTT over TLS: the CA certificate that signed the broker's")
      ->type_name("FILE");
  sub->add_option("--mqtt-user", cfg.mqtt_user, "MQTT user name")->type_name("NAME");
  sub->add_option("--mqtt-password", cfg.mqtt_password,
                  "MQTT password (default: the environment variable LUXLOC_MQTT_PASSWORD, which ps does not show)")
      ->type_name("TEXT");
  sub->add_option("--web", cfg.web,
                  "serve a read-only live view (map, trajectory, pose, rates) to browsers on [HOST:]PORT; "
                  "127.0.0.1 unless HOST is given (0.0.0.0: every interface)")
      ->type_name("[HOST:]PORT");
  sub->add_option("--web-token", cfg.web_token, "the live view requires ?token=TEXT in its URL (for --web on a network)")
      ->type_name("TEXT");
  sub->add_option("--output-rate", cfg.fusion.output_rate_hz, "pose output rate, Hz (0 = every IMU sample)")
      ->check(CLI::Range(0.0, 10000.0))
      ->capture_default_str();
  sub->add_flag("--realtime", cfg.realtime, "pace playback at the recorded speed");
  sub->add_option("--threads", cfg.threads, "worker threads for the filter (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  sub->add_option("--clock-offset", cfg.clock_offsets,
                  "add SECONDS to every time stamp of a source (e.g. frames=-0.012 for a camera-IMU offset)")
      ->type_name("SOURCE=SECONDS");
  sub->add_option("--ahrs-kp", cfg.fusion.ahrs.kp, "Mahony proportional gain (trust in gravity/north vs gyro)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  sub->add_option("--ahrs-ki", cfg.fusion.ahrs.ki, "Mahony integral gain (gyro bias learning)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  // "!--no-X" binds the negation to the bool: a value that is not true/false/on/off/yes/no
  // (`--no-uwb=abc`, `no-uwb=abc` in a config) is CLI11's ConversionError, exit 2. A flag
  // function (int64) instead let std::stoll's invalid_argument out: an abort (fuzz_config).
  sub->add_flag("!--no-accelerometer", cfg.fusion.use_accelerometer,
                "constant-velocity prediction (ignore the accelerometer; = --motion cv)");
  sub->add_option_function<std::string>(
         "--start",
         [&cfg](const std::string& v) {
           std::vector<double> n;
           std::stringstream in(v);
           std::string part;
           while (std::getline(in, part, ',')) {
             try {
               std::size_t used = 0;
               n.push_back(std::stod(part, &used));
               if (used != part.size() || !std::isfinite(n.back())) throw std::invalid_argument(part);
             } catch (const std::exception&) {
               throw CLI::ValidationError("--start", "'" + v + "': expected X,Y or X,Y,YAW (m, m, rad), got '" + part + "'");
             }
           }
           if (n.size() < 2 || n.size() > 3)
             throw CLI::ValidationError("--start", "'" + v + "': expected X,Y or X,Y,YAW (m, m, rad)");
           StartPose p = cfg.fusion.start.value_or(StartPose{});
           p.p_inW = {n[0], n[1]};
           p.yaw = n.size() == 3 ? n[2] : std::numeric_limits<double>::quiet_NaN();
           cfg.fusion.start = p;
         },
         "start the filter at this pose (m, m[, rad CCW from east]) without an absolute source: dead reckoning "
         "from a known start (overrides session.yaml's start:)")
      ->type_name("X,Y[,YAW]");
  sub->add_option("--start-sigma", cfg.fusion.start_sigma_m,
                  "1 sigma per axis of the start (--start or session.yaml's start:), m (default: the start's own, 0.1)")
      ->check(CLI::PositiveNumber)
      ->type_name("M");
  sub->add_flag("!--no-heading-state", cfg.fusion.pf.heading.enabled,
                "keep the AHRS yaw as the heading (no yaw-offset state in the filter, no feedback into the AHRS; "
                "for comparisons, docs/MOTION.md \"Heading\")");
  sub->add_option("--absolute-for", cfg.fusion.absolute_for_s,
                  "use absolute corrections (VLC, fixes) only for S seconds after initialisation, then dead-reckon")
      ->check(CLI::PositiveNumber)
      ->type_name("S");
  add_particle_filter_options(sub, cfg.fusion.pf);
  sub->add_flag("--check-associations", cfg.check_associations,
                "simulated sessions over a map that reuses frequencies: count the blobs whose copy the fusion got "
                "wrong, against the simulator's truth (groundtruth.csv with attitude; issue 14)");
  sub->add_option("--record", cfg.record,
                  "also record every input sample into this new session folder (replay with --playback)")
      ->type_name("DIR");
  sub->add_option("--uwb-likelihood", cfg.uwb_likelihood,
                  "UWB weighting: robust (Gaussian core + one-sided NLOS tail) | gaussian (plain)")
      ->check(CLI::IsMember({"robust", "gaussian"}))
      ->capture_default_str();
  sub->add_option("--uwb-range-sigma", cfg.uwb.noise.range_sigma_m, "UWB line-of-sight range noise, m (1 sigma)")
      ->check(CLI::Range(0.001, 10.0))
      ->capture_default_str();
  sub->add_option("--uwb-aoa-sigma", cfg.uwb.noise.aoa_sigma_rad, "UWB angle-of-arrival noise, rad (1 sigma)")
      ->check(CLI::Range(0.0001, 3.0))
      ->capture_default_str();
  sub->add_option("--uwb-nlos-prob", cfg.uwb.noise.nlos_probability, "prior probability of a NLOS UWB measurement")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  sub->add_option("--uwb-nlos-bias", cfg.uwb.noise.nlos_bias_mean_m, "mean positive range bias of a NLOS measurement, m")
      ->check(CLI::Range(0.01, 20.0))
      ->capture_default_str();
  sub->add_option("--attitude-sigma", cfg.attitude_sigma_rad,
                  "tilt error of the attitude (roll / pitch, 1 sigma, rad) the camera's bearings and heights allow "
                  "for (default 0.01; 0.05 with --platform drone: a multirotor's accelerometer sees thrust, not "
                  "gravity)")
      ->check(CLI::Range(0.0001, 0.5));
  sub->add_flag("--no-innovation-bias", cfg.no_innovation_bias,
                "report the filter's own spread as sigma_x / sigma_y, without the persistent bias of the fixes' "
                "innovations (docs/MOTION.md \"Honest sigma\"; for comparisons)");
  sub->add_flag("--no-gait-regression", cfg.no_gait_regression,
                "pdr: do not re-centre the particles' step-length scale and turn slowdown on the least-squares fit "
                "of the tracked stretches when an outage starts (docs/MOTION.md \"Gait fitted to the track\"; for "
                "comparisons)");
  sub->add_flag("--no-impact-filter", cfg.no_impact_filter,
                "pdr: keep heel-strike impacts in the vertical acceleration the steps are found in "
                "(core/imu/impact_filter.hpp; for comparisons)");
  sub->add_flag("--no-lever-arm", cfg.no_lever_arm,
                "pdr: do not learn where the device is held from the body's turning axis (turns on the spot; "
                "core/imu/lever_arm.hpp, docs/MOTION.md \"Lever arm\"; for comparisons)");
  sub->add_flag("--no-frame-derotation", cfg.no_frame_derotation,
                "read every frame with the attitude of the IMU sample after it, all rows alike (no turning back "
                "to the exposure; docs/MOTION.md \"Frames read at their exposure\"; for comparisons)");
  sub->add_flag("--no-heading-decouple", cfg.no_heading_decouple,
                "do not shuffle the particles' yaw offsets before the first fix after an outage (docs/MOTION.md "
                "\"Gait fitted to the track\"; for comparisons)");
  sub->add_option("--innovation-bias-tau", cfg.fusion.innovation_bias.time_constant_s,
                  "memory of the fixes' mean innovation that widens the reported sigma, s")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  sub->add_option("--camera-height", cfg.camera_height,
                  "estimate the device height from the camera geometry (two identified LEDs in view) and weigh the "
                  "frames at it; z and sigma_z are then estimated: auto (on for --platform drone), on, off (the "
                  "nominal device_height_m: a walker's planar case); docs/PLATFORMS.md")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  sub->add_option("--uwb-height", cfg.uwb_height,
                  "estimate the device height from the UWB ranges: auto (>= 4 anchors, some >= 0.5 m below and "
                  "some above the nominal height), on, off (the nominal device_height_m)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  sub->add_option("--uwb-bias", cfg.uwb_bias,
                  "learn a range bias per UWB anchor while running: auto (>= 4 anchors), on, off")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  sub->add_option("--uwb-scale", cfg.uwb_scale,
                  "learn a range scale per UWB anchor too (with the learnt bias): on, off. Off by default: within "
                  "a minute's flight the scale is barely observable (docs/PLATFORMS.md)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  sub->add_option("--uwb-online-psd", cfg.uwb_online_psd,
                  "white-acceleration psd of the online height / bias filter's motion model, horizontal,vertical "
                  "((m/s^2)^2/Hz)")
      ->expected(2)
      ->delimiter(',')
      ->check(CLI::Range(1e-6, 1e3))
      ->type_name("H,V");
  sub->add_flag("--uwb-alone", cfg.uwb.fixes_only,
                "output the raw UWB position fixes (TOF+AOA or multilateration), no filter: the UWB-alone baseline");
  sub->add_flag("--vo", cfg.vo.enabled,
                "visual odometry from a downward camera over the floor (frames + camera.yaml): velocity updates");
  sub->add_option("--vo-sigma", cfg.vo.velocity_sigma_mps, "visual-odometry velocity noise, m/s (1 sigma)")
      ->check(CLI::Range(0.001, 10.0))
      ->capture_default_str();
  sub->add_option("--vo-heading-tau", cfg.vo.heading_tau_s,
                  "VO heading: visual yaw increments from the start yaw, pulled to the attitude yaw with this "
                  "time constant, s (0: never pulled)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  sub->add_flag("!--no-uwb", cfg.uwb.enabled, "ignore UWB samples");
  sub->add_option("--status", cfg.status,
                  "one-line live status on stderr: auto (when stderr is a terminal), on, off")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  sub->add_flag("-q,--quiet", cfg.quiet, "no report on stderr");
}

void add_particle_filter_options(CLI::App* sub, ParticleFilterOptions& pf) {
  const char* g = "Particle filter";
  sub->add_option("--gait-scale", pf.gait.scale0,
                  "pdr: the step-length scale the filter starts from (a walker's calibrated k from an earlier run; "
                  "docs/MOTION.md)")
      ->check(CLI::Range(pf.gait.min_scale, pf.gait.max_scale))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--gait-scale-sigma", pf.gait.scale_sigma0,
                  "pdr: initial spread (1 sigma) of the step-length scale the fixes calibrate (docs/MOTION.md)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--gait-turn-noise", pf.gait.turn_noise,
                  "pdr: share of each step's turn that is uncertain along and across the walk")
      ->check(CLI::Range(0.0, 2.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--gait-scale-walk", pf.gait.scale_walk,
                  "pdr: random walk of the step-length scale, 1 sigma per sqrt(s)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--dr-scale-sigma", pf.gait.dead_reckoning_scale_sigma,
                  "pdr: the least spread (1 sigma) of the step-length scale once an outage lasts 1.5 s, so sigma "
                  "grows with the gait model's error from one stretch to the next (docs/MOTION.md)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--dr-heading-sigma", pf.gait.dead_reckoning_heading_offset_sigma,
                  "pdr: the least spread (1 sigma, rad) of the walking-direction offset in an outage, as "
                  "--dr-scale-sigma")
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--genetic-threshold", pf.genetic.threshold,
                  "gpf: a particle is excellent when w / max w >= this (SEEDS.md B.5a)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--genetic-alpha", pf.genetic.alpha, "gpf: crossover weight of the excellent parent (B.5b)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_flag_callback("--genetic-as-published", [&pf] { pf.genetic.preserve_spread = false; },
                "gpf: the seed's genetic step alone, without restoring the spread it removes (an "
                "overconfident filter; docs/FILTERS.md)")
      ->group(g);
  sub->add_option("--mutation-p", pf.genetic.mutation_probability, "gpf: mutation probability (B.5c)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--mutation-scale", pf.genetic.mutation_position_m, "gpf: mutation scale on x, y, m (B.5c)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--mutation-velocity", pf.genetic.mutation_velocity_mps, "gpf: mutation scale on vx, vy, m/s")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str()
      ->group(g);
  sub->add_flag("--kld", pf.kld.enabled, "adaptive particle count by KLD-sampling (Fox 2003, as AMCL)")->group(g);
  sub->add_option("--kld-epsilon", pf.kld.epsilon, "KLD-sampling error bound")
      ->check(CLI::Range(1e-4, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--kld-bin", pf.kld.bin_m, "KLD-sampling position bin, m")
      ->check(CLI::Range(1e-3, 10.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--search-kld-epsilon", pf.search_kld.epsilon,
                  "global search (frequency reuse): KLD-sampling error bound that sizes the search's set")
      ->check(CLI::Range(1e-4, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--search-kld-bin", pf.search_kld.bin_m, "global search: KLD-sampling position bin, m")
      ->check(CLI::Range(1e-3, 10.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--min-particles", pf.kld.min_particles, "KLD-sampling lower bound")
      ->check(CLI::Range(10, 10'000'000))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--max-particles", pf.kld.max_particles, "KLD-sampling upper bound")
      ->check(CLI::Range(10, 10'000'000))
      ->capture_default_str()
      ->group(g);
  sub->add_flag("--inject", pf.injection.enabled,
                "random-particle injection when the likelihood drops (kidnapping; over the LED map's extent)")
      ->group(g);
  sub->add_option("--inject-alpha-slow", pf.injection.alpha_slow, "injection: slow average rate")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
  sub->add_option("--inject-alpha-fast", pf.injection.alpha_fast, "injection: fast average rate")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(g);
}

void for_each_frame(OpenedSources& opened, const std::function<bool()>& more,
                    const std::function<void(const FrameSample&)>& visit) {
  for (SourcePtr& src : opened.session.sources) {
    SensorData d;
    while (more() && src->next(d))
      if (const auto* f = std::get_if<FrameSample>(&d)) visit(*f);
    src->request_stop();
  }
}

std::optional<double> measured_row_time_us(const std::string& camera_path) {
  const CameraModel cam = CameraModel::load(camera_path);  // validates the file (InputError naming key)
  if (!cam.row_time_known) return std::nullopt;            // CameraModel's 30 us guess: never shift stamps by it
  return cam.row_time_s * 1e6;
}

OpenedSources open_run_sources(const RunConfig& c) {
  for (const std::string& path : c.plugins) register_external_plugin(path);
  std::vector<std::string> playback_dirs;
  std::vector<SourcePtr> live;
  LiveSessionDefaults live_defaults;
  if (!c.playback.empty()) playback_dirs.push_back(c.playback);
  // A V4L2 camera whose driver stamps the end of each frame needs the row time to move
  // its frames to row 0's exposure start: from --camera when the source does not give it.
  const std::optional<double> camera_row_time_us = c.camera.empty() ? std::nullopt : measured_row_time_us(c.camera);
  for (const auto& text : c.sources) {
    SourceSpec spec = SourceSpec::parse(text);
    if (spec.kind == "v4l2" && camera_row_time_us && !spec.params.count("row_time_us"))
      spec.params["row_time_us"] = std::to_string(*camera_row_time_us);
    if (spec.kind == "playback") {
      playback_dirs.push_back(spec.target);
    } else {
      live.push_back(make_live_source(spec));
      live_session_defaults(spec, live_defaults);
    }
  }
  if (playback_dirs.empty() && live.empty())
    throw InputError("run", 0, "--playback", "no source: give --playback DIR or --source KIND:TARGET");
  if (playback_dirs.size() > 1) throw InputError("run", 0, "--playback", "one playback session per run");

  PlaybackOptions popt;
  popt.map_path = c.map;
  popt.camera_path = c.camera;
  OpenedSources o;
  PlaybackSession& session = o.session;
  if (!playback_dirs.empty()) {
    session = open_playback(playback_dirs.front(), popt);
  } else {
    if (!c.map.empty()) session.map = LedMap::load(c.map, popt.map_options);
    if (!c.camera.empty()) session.camera = CameraModel::load(c.camera);
    session.config = live_defaults.config;
  }
  if (!session.map) session.map = std::move(live_defaults.map);
  if (!session.camera) session.camera = std::move(live_defaults.camera);
  if (session.map && session.camera)  // SPEC.md: no two LEDs of one frequency class in one view
    check_frequency_reuse(*session.map, *session.camera, session.config.device_height_m,
                          !c.map.empty() ? c.map
                          : !playback_dirs.empty() ? (std::filesystem::path(playback_dirs.front()) / session.config.ledmap_file).string()
                                                   : std::string("the source's LED map"));
  o.live = !live.empty();
  for (auto& s : live) session.sources.push_back(std::move(s));

  o.pipeline.realtime = c.realtime;
  // Live merging (reorder window, drops instead of waiting) for sources that follow the
  // wall clock; a live source that runs ahead of it (sim: with realtime=0) can wait.
  o.pipeline.live = false;
  for (const auto& s : session.sources) o.pipeline.live = o.pipeline.live || (s->live() && s->clock_follows_arrival());
  o.pipeline.clock_offsets_ns.assign(session.sources.size(), 0);
  for (const auto& co : c.clock_offsets) {
    const auto eq = co.find('=');
    if (eq == std::string::npos)
      throw InputError("--clock-offset", 0, "--clock-offset", "'" + co + "': expected SOURCE=SECONDS");
    const std::string name = co.substr(0, eq);
    const double secs = parse_seconds(co.substr(eq + 1), co);
    bool found = false;
    for (std::size_t i = 0; i < session.sources.size(); ++i) {
      const std::string sn = session.sources[i]->name();
      if (sn == name || sn.rfind(name, 0) == 0) {
        o.pipeline.clock_offsets_ns[i] = seconds_to_ns(secs);
        found = true;
      }
    }
    if (!found) throw InputError("--clock-offset", 0, "--clock-offset", "'" + co + "': no source named '" + name + "'");
  }
  return o;
}

PipelineReport run_with_stop_signals(Pipeline& pipeline, FusionStage& stage) {
  StopSignals signals(pipeline);
  return pipeline.run(stage);
}

RunOutcome run_session(const RunConfig& cfg, std::ostream& log) {
  std::unique_ptr<tbb::global_control> threads;
  if (cfg.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    static_cast<std::size_t>(cfg.threads));
  RunConfig c = cfg;
  c.fusion.pf.scheme = parse_resampling_scheme(cfg.resampling);
  c.fusion.tight_coupling = cfg.coupling == "tight";
  c.uwb.noise.likelihood = cfg.uwb_likelihood == "gaussian" ? UwbLikelihood::gaussian : UwbLikelihood::robust;
  const auto online = [](const std::string& v) {
    return v == "on" ? UwbOnline::on : v == "off" ? UwbOnline::off : UwbOnline::automatic;
  };
  c.uwb.height = online(cfg.uwb_height);
  c.uwb.bias = online(cfg.uwb_bias);
  c.uwb.scale = online(cfg.uwb_scale);
  if (cfg.uwb_online_psd.size() == 2) {
    c.uwb.online.horizontal_accel_psd = cfg.uwb_online_psd[0];
    c.uwb.online.vertical_accel_psd = cfg.uwb_online_psd[1];
  }
  // auto: a pedestrian (pdr), except with visual odometry, seed C's strapdown + VO (the VO
  // scenario is a smooth ride without steps, where pdr would see a still device).
  // --platform names the model; else the data decide: pdr behind the gait gate.
  const std::string platform_model = cfg.platform == "pedestrian" || cfg.platform == "handheld" ? "pdr"
                                     : cfg.platform == "robot" || cfg.platform == "vehicle"   ? "cv"
                                     : cfg.platform == "drone"                                ? "strapdown"
                                                                                              : "";
  const bool by_data = cfg.motion == "auto" && platform_model.empty() && !cfg.vo.enabled;
  c.fusion.motion.model = parse_motion_model(cfg.motion != "auto"     ? cfg.motion
                                             : !platform_model.empty() ? platform_model
                                             : cfg.vo.enabled          ? "strapdown"
                                                                       : "pdr");
  c.fusion.motion.gait_gate = by_data;
  // The attitude's tilt error the camera's bearings and heights allow for: a walker's or a
  // robot's AHRS holds roll / pitch within ~0.01 rad; a multirotor's accelerometer sees its
  // thrust, not gravity, whenever it accelerates, so its tilt is off by more (sim drone
  // seed 1, tuning: 0.05 rad rms). 0.05 for a drone: on drone seeds 1-5 with --camera the
  // share of poses within their 95 % ellipse went 27-53 % (0.01) -> 75-85 % (0.03) ->
  // 87-98 % (0.05), ATE 0.15-0.20 m either way.
  c.fusion.attitude_sigma_rad = cfg.attitude_sigma_rad > 0.0 ? cfg.attitude_sigma_rad
                                : cfg.platform == "drone"     ? 0.05
                                                              : FusionOptions{}.attitude_sigma_rad;
  if (cfg.no_innovation_bias) c.fusion.innovation_bias.enabled = false;
  if (cfg.no_gait_regression) c.fusion.gait_regression.enabled = false;
  if (cfg.no_impact_filter) c.fusion.motion.pdr.impacts.max_jump_mps2 = 0.0;
  if (cfg.no_heading_decouple) c.fusion.decouple_heading_after_outage = false;
  if (cfg.no_lever_arm) c.fusion.motion.lever_arm = false;
  if (cfg.no_frame_derotation) {
    c.fusion.max_attitude_backdate_s = 0.0;
    c.fusion.derotate_rows = false;
  }
  if (cfg.platform == "drone") c.fusion.vlc_frame_correlation = 2.0;  // FusionOptions::vlc_frame_correlation
  c.fusion.camera_height = cfg.camera_height == "on" || (cfg.camera_height == "auto" && cfg.platform == "drone");
  if (!cfg.imu_calib.empty()) c.fusion.imu_calibration = load_imu_calibration(cfg.imu_calib);

  OpenedSources opened = open_run_sources(c);
  PlaybackSession& session = opened.session;
  if (!session.map && !c.vo.enabled) log << "luxloc: note: no LED map: camera frames will be ignored\n";
  if (c.fusion.pf.injection.enabled && c.fusion.pf.injection.region.isEmpty()) {
    // Injected particles are drawn where the device can be: under the lights, 1 m around.
    if (!session.map || session.map->empty())
      throw InputError("--inject", 0, "--inject", "random-particle injection needs an LED map for its region");
    for (const Led& l : session.map->leds()) c.fusion.pf.injection.region.extend(l.p_inW.head<2>());
    c.fusion.pf.injection.region.min() -= Eigen::Vector2d::Constant(1.0);
    c.fusion.pf.injection.region.max() += Eigen::Vector2d::Constant(1.0);
  }
  if (!session.camera) log << "luxloc: note: no camera file: camera frames will be ignored\n";

  // Sinks.
  std::vector<PoseSinkPtr> sinks;
  const std::string out = c.out.empty() && c.udp.empty() && c.mqtt.empty() && c.web.empty() ? "-" : c.out;
  if (!out.empty()) sinks.push_back(make_pose_file_sink(out, parse_pose_format(c.format)));
  for (const auto& u : c.udp) sinks.push_back(std::make_unique<UdpPoseSink>(u));
  auto counters = std::make_shared<SampleCounters>(session.sources.size());
  RunMonitor monitor;
  monitor.counters = counters;
  for (const auto& src : session.sources) {
    monitor.source_names.push_back(src->name());
    monitor.source_drops.push_back(&src->drops());
  }
  if (!c.mqtt.empty()) {
    MqttOptions mo;
    mo.device_id = c.device_id;
    mo.tls_ca = c.mqtt_tls_ca;
    mo.user = c.mqtt_user;
    mo.password = c.mqtt_password;
    if (mo.password.empty())
      if (const char* env = std::getenv("LUXLOC_MQTT_PASSWORD")) mo.password = env;
    for (const auto& m : c.mqtt) sinks.push_back(std::make_unique<MqttPoseSink>(m, mo, monitor));
  } else if (!c.device_id.empty()) {
    check_device_id(c.device_id);
  }
  LiveViewSink* live_view = nullptr;  // owned by the pipeline's sinks
  if (!c.web.empty()) {
    LiveViewOptions wo;
    wo.token = c.web_token;
    wo.device_id = c.device_id.empty() ? default_device_id() : c.device_id;
    auto view = std::make_unique<LiveViewSink>(c.web, wo, monitor, session.map);
    if (!c.quiet) log << "luxloc: live view on " << view->url() << "\n";
    live_view = view.get();
    sinks.push_back(std::move(view));
  } else if (!c.web_token.empty()) {
    throw InputError("--web-token", 0, "", "a token without --web");
  }
  // The live status line: on a terminal (or --status on), never into a pipe or a log file.
  if (c.status == "on" || (c.status == "auto" && !c.quiet && isatty(fileno(stderr)) && out != "-")) {
    std::vector<std::string> names;
    for (const auto& src : session.sources) names.push_back(src->name());
    TimeNs t_first = 0, t_last = 0;
    const bool span = !c.playback.empty() && session_time_span(c.playback, t_first, t_last);
    sinks.push_back(std::make_unique<StatusLine>(names, counters, span ? ns_to_seconds(t_last - t_first) : 0.0, t_first));
  }

  FusionEngine engine(c.fusion, session.map, session.camera, session.config, c.uwb, c.vo);
  // --check-associations: the truth is read before the run (a bad file stops it at once).
  SimTruth assoc_truth;
  std::vector<std::pair<double, double>> assoc_blackouts;
  std::vector<FusionEngine::AssociationRecord> assoc_records;  // written on the fusion thread, read after it
  if (c.check_associations) {
    if (c.playback.empty() || !session.groundtruth)
      throw InputError("--check-associations", 0, "", "needs a simulated --playback session with groundtruth.csv");
    if (!session.map || !session.camera)
      throw InputError("--check-associations", 0, "", "needs the session's LED map and camera file");
    assoc_truth = read_truth(*session.groundtruth);
    if (!assoc_truth.has_tilt || !assoc_truth.has_z || assoc_truth.rows.size() < 2)
      throw InputError(session.groundtruth->string(), 0, "roll",
                       "--check-associations needs the simulator's groundtruth.csv (t,x,y,z,yaw,roll,pitch)");
    assoc_blackouts = read_blackouts(std::filesystem::path(c.playback) / "sim_truth.yaml");
    if (!session.map->reuses_frequencies())
      log << "luxloc: note: --check-associations: the map gives every LED a frequency of its own: nothing to check\n";
    engine.set_association_observer(
        [&assoc_records](const FusionEngine::AssociationRecord& r) { assoc_records.push_back(r); });
  }
  if (live_view)
    engine.set_frame_observer([live_view](const FrameSample& f, const std::vector<LedObservation>& leds) {
      live_view->offer_frame(f, leds);
    });
  if (live_view)
    engine.set_cloud_observer([live_view](const std::vector<Eigen::Vector2d>& cloud) { live_view->offer_cloud(cloud); },
                              std::chrono::milliseconds(333), 300);
  std::unique_ptr<SessionRecorder> recorder;
  if (!c.record.empty())
    recorder = std::make_unique<SessionRecorder>(c.record, session.map, session.camera, session.config);
  opened.pipeline.probe = c.probe;
  Pipeline pipeline(std::move(session.sources), std::move(sinks), opened.pipeline);
  RunOutcome outcome;
  if (recorder) {
    TeeStage tee(*recorder, engine);
    CountingStage counted(tee, counters);
    outcome.pipeline = run_with_stop_signals(pipeline, counted);
    std::vector<PoseEstimate> none;
    recorder->finish(none);
    if (const std::string e = recorder->error(); !e.empty())
      outcome.failures += "record: " + e + "; the recording stopped there, the fusion went on\n";
    const RecorderStats st = recorder->error().empty() ? recorder->stats() : RecorderStats{};
    for (const auto& [file, n] : st.dropped)
      outcome.failures += "record: " + std::to_string(n) + " samples for " + file + " dropped (disk too slow)\n";
  } else {
    CountingStage counted(engine, counters);
    outcome.pipeline = run_with_stop_signals(pipeline, counted);
  }
  outcome.fusion = engine.stats();
  outcome.uwb = engine.uwb_stats();
  outcome.vo = engine.vo_stats();
  outcome.groundtruth = session.groundtruth;
  if (c.check_associations)
    outcome.associations = check_associations(assoc_records, assoc_truth, assoc_blackouts, *session.camera, *session.map);
  for (const auto& s : outcome.pipeline.sources)
    if (!s.failure.empty()) outcome.failures += s.name + ": " + s.failure + "\n";
  if (!outcome.pipeline.output_failure.empty())
    outcome.failures += "output " + outcome.pipeline.output_failure + "; the run stopped\n";
  if (!c.quiet) print_report(outcome, log);
  return outcome;
}

void print_report(const RunOutcome& r, std::ostream& log) {
  const auto& p = r.pipeline;
  log << std::fixed << std::setprecision(2);
  log << "luxloc: " << (p.stopped ? "stopped" : "done") << ": " << p.poses << " poses over " << p.data_span_s()
      << " s of data in " << p.wall_s << " s wall (" << (p.wall_s > 0 ? p.data_span_s() / p.wall_s : 0.0)
      << "x real time)\n";
  for (const auto& s : p.sources) {
    log << "  source " << s.name << ": " << s.samples << " samples";
    for (const auto& [reason, e] : s.drops) log << ", " << e.count << " skipped (" << reason << ")";
    log << "\n";
    for (const auto& [reason, e] : s.drops) {
      if (e.first_message.empty()) continue;
      log << "    first " << reason << ": " << e.first_message << "\n";
      for (std::size_t i = 1; i < e.messages.size(); ++i) log << "    " << reason << ": " << e.messages[i] << "\n";
      const std::uint64_t named = std::max<std::uint64_t>(e.messages.size(), 1);
      if (e.count > named) log << "    (" << e.count - named << " more " << reason << " not listed)\n";
    }
    // The lag behind its stamps: what the merger waits for (core/pipeline/source_lag.hpp).
    if (s.lag_samples)
      log << "    arrived " << std::setprecision(0) << 1e3 * s.lag_mean_s << " ms after its stamps (mean; max "
          << 1e3 * s.lag_max_s << " ms)\n"
          << std::setprecision(2);
    if (s.silences) log << "    silent " << s.silences << "x, came back each time (longest " << s.longest_silence_s << " s)\n";
    if (s.clock_jumps)
      log << "    clock jumped " << s.clock_jumps << "x, re-based onto the arrival clock (first jump " << std::showpos
          << s.first_clock_jump_s << std::noshowpos << " s)\n";
    if (!s.failure.empty()) log << "    FAILED: " << s.failure << "\n";
  }
  const FusionStats& f = r.fusion;
  log << "  fusion: imu " << f.imu_samples << " (" << f.imu_rejected << " rejected), frames " << f.frames << " ("
      << f.frames_with_leds << " with LEDs, " << f.leds_decoded << " LEDs identified, " << f.blobs_rejected
      << " blobs refused), fixes " << f.fixes_accepted << " used / " << f.fixes_gated << " gated, "
      << f.reinitializations << " re-initialisations";
  if (f.frames_without_attitude) log << ", " << f.frames_without_attitude << " frames before the IMU aligned";
  if (f.other_samples) log << ", " << f.other_samples << " samples of kinds this filter does not use";
  if (f.corrections_ignored) log << ", " << f.corrections_ignored << " absolute samples ignored (--absolute-for)";
  log << "\n";
  if (!f.motion.empty()) {
    log << "  motion: " << f.motion;
    if (f.motion_auto) {
      // The mode over time (issue 16): walking with the pedestrian model, or not.
      log << ", " << f.steps << " steps (auto: " << f.steps_used
          << (f.steps_used > 0 ? " in a gait" : " used, no gait seen") << "); mode: walking " << std::setprecision(1)
          << f.regime_s[2] << " s, moving without steps (strapdown) " << f.regime_s[1] << " s, still "
          << f.regime_s[3] << " s" << std::setprecision(2);
    } else if (f.motion == "pdr") {
      log << ", " << f.steps << " steps";
    }
    if (f.turning_in_place_s > 0.0)
      log << ", held in place while turning on the spot " << std::setprecision(1) << f.turning_in_place_s << " s"
          << std::setprecision(2);
    if (f.lever_turns > 0)
      log << ", device held " << std::setprecision(2) << f.lever_forward_m << " m forward, " << f.lever_left_m
          << " m left of the turning axis (from " << f.lever_turns << " turn(s) on the spot)";
    if (f.impact_samples) log << ", " << f.impact_samples << " samples of heel-strike impacts replaced";
    if (std::isfinite(f.gait_scale))
      log << ", gait calibrated to step-length scale " << std::setprecision(3) << f.gait_scale
          << ", heading offset " << std::setprecision(2) << f.gait_heading_offset_rad * 180.0 / 3.141592653589793
          << " deg";
    log << std::setprecision(2) << "\n";
  }
  if (f.heading_transfers || f.camera_yaw_used || f.camera_yaw_rejected || std::isfinite(f.sigma_yaw_rad)) {
    log << "  heading: " << f.heading_transfers << " corrections of the AHRS yaw, gyro z bias learnt "
        << std::setprecision(3) << -f.heading_learnt_rate_rps * 180.0 / 3.141592653589793 << " deg/s";
    if (f.camera_yaw_used || f.camera_yaw_rejected)
      log << ", camera yaw " << f.camera_yaw_used << " used / " << f.camera_yaw_rejected << " gated";
    if (std::isfinite(f.sigma_yaw_rad)) log << ", final sigma_yaw " << f.sigma_yaw_rad * 180.0 / 3.141592653589793 << " deg";
    log << std::setprecision(2) << "\n";
  }
  if (f.poses_lag_widened && f.poses)
    log << "  sigma: " << std::setprecision(1) << 100.0 * static_cast<double>(f.poses_lag_widened) / static_cast<double>(f.poses)
        << " % of the poses mostly widened by the fixes' persistent innovation (the filter lagging its fixes, "
           "docs/MOTION.md \"Honest sigma\"), by up to "
        << std::setprecision(2) << f.max_lag_sigma_m << " m\n";
  if (f.gait_recentred || f.headings_decoupled)
    log << "  gait: re-centred on the fit to the tracked stretches at " << f.gait_recentred
        << " outage start(s), the step-length scale by up to " << std::setprecision(3) << f.max_gait_recentre_scale
        << std::setprecision(2) << (f.headings_decoupled ? ", yaw offsets shuffled before the first fix after " : "")
        << (f.headings_decoupled ? std::to_string(f.headings_decoupled) + " of them" : std::string())
        << " (docs/MOTION.md \"Gait fitted to the track\")\n";
  if (f.camera_heights_used || f.camera_heights_gated || std::isfinite(f.final_height_m)) {
    log << "  height from the camera: " << f.camera_heights_used << " heights used (LED pairs, LED sizes) / "
        << f.camera_heights_gated << " gated" << (f.camera_height_in_uwb ? " (into the UWB height filter)" : "");
    if (f.camera_height_reopened) log << ", " << f.camera_height_reopened << " reopened (a run of gated heights)";
    if (std::isfinite(f.final_height_m))
      log << std::setprecision(3) << ", final z " << f.final_height_m << " m +/- " << f.final_height_sigma_m;
    log << std::setprecision(2) << "\n";
  }
  // The nominal device height against the camera's: a misstated device_height_m moves every
  // VLC fix by (error) x tan(the LED's angle), and the user cannot see why. Warned when the
  // camera disagrees by more than 0.1 m and 3 sigma over at least 30 heights.
  if (f.height_check_used >= 30 && std::isfinite(f.height_check_m) &&
      std::abs(f.height_check_m - f.nominal_height_m) > std::max(0.1, 3.0 * f.height_check_sigma_m))
    log << std::setprecision(3) << "luxloc: warning: the camera measures the device at " << f.height_check_m
        << " m +/- " << f.height_check_sigma_m << " (" << f.height_check_used << " heights), not at the nominal "
        << f.nominal_height_m << " m (device_height_m / --device-height): correct it, or run with --camera-height on\n"
        << std::setprecision(2);
  if (f.reused_blobs || f.global_starts || f.global_restarts) {
    log << "  frequency reuse: " << f.reused_blobs << " blobs of reused frequencies (each particle chose the copy); "
        << f.global_starts << " global starts, " << f.global_restarts << " global restarts (lost track)";
    // Each search (start, time to converge); the first ones of a long run, then a count.
    const std::size_t shown = std::min<std::size_t>(f.global_searches.size(), 6);
    for (std::size_t i = 0; i < shown; ++i) {
      const FusionStats::GlobalSearch& g = f.global_searches[i];
      log << (i ? "; " : ": ") << "search from t = " << std::setprecision(1) << g.t_start_s << " s (" << g.particles
          << " particles) ";
      if (std::isfinite(g.converged_after_s))
        log << "converged after " << g.converged_after_s << " s";
      else
        log << "did not converge";
    }
    if (f.global_searches.size() > shown) log << "; " << f.global_searches.size() - shown << " more searches";
    log << std::setprecision(2) << "\n";
  }
  if (r.associations) log << "  " << describe(*r.associations) << "\n";
  const UwbStats& u = r.uwb;
  if (u.samples) {
    // One line whose parts add up to the measurements (issue 16 part 6).
    log << "  uwb: " << u.samples << " measurements = " << u.weighed + u.fixes_used << " used (" << u.weighed
        << " ranges weighed by the filter, " << u.fixes_used << " as position fixes) + " << u.fixes_gated
        << " fixes gated + " << u.reinitializations << " restarted the filter + " << u.no_fix
        << " waiting for a fix"
        << (u.start_held ? " (" + std::to_string(u.start_held) + " fixes held until consecutive fixes agreed on a start)"
                         : std::string())
        << " + " << u.underflow << " refused (all weights underflowed) + "
        << u.nlos_set_aside << " set aside (anchor in NLOS) + " << u.unknown_anchor + u.rejected << " rejected ("
        << u.unknown_anchor
        << " from unknown anchors (not in session.yaml), " << u.rejected << " unusable)";
    if (u.accounted() != u.samples) log << " [" << u.samples - u.accounted() << " unaccounted]";
    log << "; " << u.fixes << " position fixes made";
    if (u.fixes_outside_hull) log << " (" << u.fixes_outside_hull << " outside the anchors: mode uwb-outside-anchors)";
    log << ", " << u.disagreements
        << " ranges far from the filter's mean (weighed all the same: a run of them restarts the filter)";
    if (u.learnt_anchors) log << ", " << u.learnt_anchors << " anchor positions taken from the device";
    log << "\n";
    if (u.online_used + u.online_gated_long + u.online_gated_short) {
      log << "  uwb online: " << u.online_used << " ranges used, " << u.online_gated_long << " set aside as NLOS (long), "
          << u.online_gated_short << " as short";
      if (u.online_bias_reopened)
        log << " (" << u.online_bias_reopened << " runs of short ranges reopened an anchor's bias)";
      if (std::isfinite(u.final_height_m))
        log << "; height " << std::setprecision(3) << u.final_height_m << " m +/- " << u.final_height_sigma_m;
      if (!u.learnt_bias_m.empty()) {
        log << "; learnt range bias (m):" << std::setprecision(2);
        for (const auto& [id, b] : u.learnt_bias_m) log << " " << id << ":" << b;
      }
      if (!u.learnt_scale.empty()) {
        log << "; scale:" << std::setprecision(4);
        for (const auto& [id, k] : u.learnt_scale) log << " " << id << ":" << k;
      }
      log << std::setprecision(2) << "\n";
    }
  }
  if (r.vo.frames)
    log << "  vo: " << r.vo.frames << " frames, " << r.vo.motions << " motions fitted, " << r.vo.accepted
        << " velocity updates used, " << r.vo.rejected << " refused\n";
  if (p.paced && p.latency.count)
    log << "  latency (newest input to the outputs): p50 " << std::setprecision(2) << 1e3 * p.latency.p50_s << " ms, p99 "
        << 1e3 * p.latency.p99_s << " ms, max " << 1e3 * p.latency.max_s << " ms over " << p.latency.count << " poses\n";
  for (const auto& sink : p.sinks)
    for (const auto& [reason, e] : sink.drops) {
      log << "  output " << sink.name << ": " << e.count << " poses not delivered (" << reason << ")";
      if (!e.first_message.empty()) log << ", first: " << e.first_message;
      log << "\n";
    }
  if (p.poses_dropped) log << "  outputs: " << p.poses_dropped << " poses dropped (output too slow)\n";
  log.unsetf(std::ios::floatfield);
}

}  // namespace luxloc::app
