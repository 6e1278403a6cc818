#pragma once
// Shared by `run` and `demo`: builds the sources, the fusion stage and the sinks from the
// options, runs the pipeline and reports what happened.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "app/association_check.hpp"
#include "core/fusion/fusion_engine.hpp"
#include "core/pipeline/pipeline.hpp"
#include "plugins/playback/playback_session.hpp"

namespace luxloc::app {

struct RunConfig {
  std::vector<std::string> sources;  // --source KIND:TARGET[,k=v...]
  std::vector<std::string> plugins;  // --plugin PATH.so (external source kinds)
  std::string playback;              // --playback DIR (= --source playback:DIR)
  std::string map, camera;           // overrides of the session's files
  FusionOptions fusion;
  UwbOptions uwb;
  VoOptions vo;
  std::string uwb_likelihood = "robust";  // robust | gaussian
  // Height from the camera geometry (issue 16 part 3): auto (on for --platform drone), on, off.
  std::string camera_height = "auto";
  double attitude_sigma_rad = 0.0;  // 0: the platform's default (run --attitude-sigma)
  bool no_innovation_bias = false;  // run --no-innovation-bias (FusionOptions::innovation_bias)
  bool no_gait_regression = false;  // run --no-gait-regression (FusionOptions::gait_regression)
  bool no_impact_filter = false;    // run --no-impact-filter (PdrOptions::impacts off)
  bool no_heading_decouple = false;  // run --no-heading-decouple (FusionOptions::decouple_heading_after_outage)
  bool no_lever_arm = false;  // run --no-lever-arm (MotionSourceOptions::lever_arm)
  bool no_frame_derotation = false;  // run --no-frame-derotation (FusionOptions::max_attitude_backdate_s, derotate_rows)
  std::string uwb_height = "auto", uwb_bias = "auto";  // auto | on | off (issue 16: learnt while running)
  std::string uwb_scale = "off";  // on | off: a per-anchor range scale beside the learnt bias
  std::vector<double> uwb_online_psd;                  // empty: HeightBiasOptions' defaults
  std::string resampling = "systematic";
  std::string coupling = "tight";    // tight | loose
  std::string motion = "auto";       // auto | pdr | strapdown | cv (docs/MOTION.md)
  std::string platform;              // empty | pedestrian | handheld | robot | vehicle | drone (issue 16)
  std::string imu_calib;             // --imu-calib FILE (luxloc calib imu)
  std::string out;                   // pose file; "-" = stdout; empty and no --udp: stdout
  std::vector<std::string> udp;      // HOST:PORT, repeatable
  std::vector<std::string> mqtt;     // HOST:PORT[/TOPIC], repeatable
  std::string device_id;             // --device-id (MQTT topics, "device" field); empty: host name
  std::string mqtt_tls_ca, mqtt_user, mqtt_password;
  std::string web;        // --web [HOST:]PORT: the live view in a browser
  std::string web_token;  // --web-token T: required as ?token=T
  std::string format = "csv";        // csv | tum
  bool realtime = false;
  int threads = 0;                   // 0 = all cores (TBB default)
  std::vector<std::string> clock_offsets;  // SOURCE=SECONDS
  bool quiet = false;
  std::string record;  // --record DIR: also write every input sample into a session folder
  bool check_associations = false;  // --check-associations: reused-frequency copies against the simulator's truth
  std::string status = "auto";  // live status line: auto (terminal) | on | off
  // Not an option: called on the fusion thread (luxloc bench soak's RSS / queue monitor).
  std::function<void(const PipelineProbe&)> probe;
};

struct RunOutcome {
  PipelineReport pipeline;
  FusionStats fusion;
  UwbStats uwb;
  VoStats vo;
  std::optional<std::filesystem::path> groundtruth;  // of the played-back session
  std::optional<AssociationCheck> associations;      // --check-associations
  std::string failures;  // sources that ended through a failure
};

// Registers the options of `run` on `sub` (also used by `demo` for a subset).
void add_run_options(CLI::App* sub, RunConfig& cfg);
// The particle filter's variant options (genetic, KLD-sampling, injection), shared with compare.
void add_particle_filter_options(CLI::App* sub, ParticleFilterOptions& pf);
// The sources of a run (--playback, --source) with the session they bring (LED map, camera,
// session.yaml; --map / --camera win) and the pipeline options (--realtime, --clock-offset).
struct OpenedSources {
  PlaybackSession session;
  bool live = false;
  PipelineOptions pipeline;
};
OpenedSources open_run_sources(const RunConfig& cfg);
// The row time camera.yaml states (us), none when it has no row_time_us (CameraModel's 30 us
// default is a guess): handed to a v4l2 source without row_time_us=, for its end-of-frame
// stamps (plugins/v4l2/v4l2_camera.hpp).
std::optional<double> measured_row_time_us(const std::string& camera_path);
// The camera frames of the opened sources, one source after another, for the calibration
// tools: visit(frame) while more() holds (checked before each read); then every source is
// asked to stop (a live camera would stream on).
void for_each_frame(OpenedSources& opened, const std::function<bool()>& more,
                    const std::function<void(const FrameSample&)>& visit);
// Runs the pipeline; SIGINT/SIGTERM stop it cleanly for the duration.
PipelineReport run_with_stop_signals(Pipeline& pipeline, FusionStage& stage);

// Runs the session; SIGINT/SIGTERM stop it cleanly (every computed pose is written).
// Throws InputError for unusable options or input files.
RunOutcome run_session(const RunConfig& cfg, std::ostream& log);
// The end-of-run report: per-source samples and drops, fusion counters, speed.
void print_report(const RunOutcome& r, std::ostream& log);

}  // namespace luxloc::app
