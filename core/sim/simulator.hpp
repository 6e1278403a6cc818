#pragma once
// A whole simulated session: a scenario plus the run's options and random draws (LED
// phases, IMU biases), from which the IMU stream, the rolling-shutter frames and the
// ground truth are produced on demand. Deterministic: same seed -> same samples.
// Thread-safe for concurrent const use (frames can be rendered in parallel).
#include <cstdint>
#include <string>
#include <optional>
#include <vector>

#include "core/common/samples.hpp"
#include <memory>

#include "core/sim/floor_renderer.hpp"
#include "core/sim/frame_renderer.hpp"
#include "core/sim/imu_synth.hpp"
#include "core/sim/mag_disturbance.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/walker_population.hpp"
#include "core/sim/world_population.hpp"

namespace luxloc::sim {

// Lights off during [start_s, start_s + duration_s) (a frame is dark when its row 0 starts
// its exposure in the interval).
struct Blackout {
  double start_s = 0.0;
  double duration_s = 0.0;
  bool contains(double t_s) const { return t_s >= start_s && t_s < start_s + duration_s; }
};

struct SimOptions {
  std::uint64_t seed = 1;
  double duration_s = 0.0;       // <= 0: the scenario's default
  double fps = 30.0;             // frame rate
  double imu_rate_hz = 100.0;    // IMU and ground-truth rate
  double frame_offset_s = 0.005; // first frame's row 0 exposure start (camera and IMU clocks differ)
  std::vector<Blackout> blackouts;
  ImuNoise imu;
  std::string mag_disturbance = "none";  // mag_disturbance_names(): steel, magnet, both
  RenderOptions render;
  // The walker drawn by `--walker random` (already in the scenario's trajectory; kept here
  // for sim_truth.yaml).
  std::optional<WalkerDraw> walker;
  // The camera mode and ceiling of `--world random` / `--camera-mode` (already in the
  // scenario's camera and map; kept here for sim_truth.yaml): what was drawn or asked for,
  // and what the frequency plan made of it.
  std::optional<WorldDraw> world;
  std::optional<CameraMode> camera_mode;
  std::optional<WorldPlan> world_plan;
  // The heel-strike impacts' peak (GaitOptions::heel_impact_mps2, `--heel-impact`), m/s^2;
  // 0: none. For sim_truth.yaml.
  double heel_impact_mps2 = 0.0;
  // A kidnap in the trajectory (kidnap_trajectory.hpp; the carry is also a blackout), for
  // sim_truth.yaml: when the device was picked up and put down, and where.
  struct Kidnap {
    double start_s = 0.0, end_s = 0.0;
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  };
  std::optional<Kidnap> kidnap;
};

class Simulator {
 public:
  // Throws std::invalid_argument on unusable options (rates <= 0, ...).
  Simulator(Scenario scenario, SimOptions options);

  const Scenario& scenario() const { return scenario_; }
  const SimOptions& options() const { return opt_; }
  double duration_s() const { return duration_s_; }
  const ImuBiases& imu_biases() const { return biases_; }  // gyro: at t = 0
  const MagneticField& magnetic_field() const { return field_; }
  // The gyro bias at each IMU sample (constant unless the grade walks it), rad/s.
  std::vector<Eigen::Vector3d> gyro_bias_track() const;
  const std::vector<double>& led_phases_s() const { return phases_s_; }  // per LED of the map

  BodyState truth(double t_s) const { return scenario_.trajectory->state(t_s); }
  std::vector<double> step_times() const { return scenario_.trajectory->step_times(duration_s_); }

  std::size_t imu_count() const;  // samples at k / imu_rate, k = 0 .. count-1, t < duration
  double imu_time_s(std::size_t k) const { return static_cast<double>(k) / opt_.imu_rate_hz; }
  std::vector<ImuSample> imu_samples() const;

  std::size_t frame_count() const;  // floor(duration * fps) frames
  double frame_time_s(std::size_t k) const { return opt_.frame_offset_s + static_cast<double>(k) / opt_.fps; }
  bool lights_on(double t_s) const;
  RenderedFrame render(std::size_t k) const;

  // The scenario's UWB measurements (empty without anchors), in time order.
  std::vector<SimUwbMeasurement> uwb_measurements() const;
  // The per-anchor range biases the measurements carry (empty: none drawn).
  std::vector<UwbAnchorBias> uwb_biases() const;

 private:
  Scenario scenario_;
  SimOptions opt_;
  double duration_s_ = 0.0;
  ImuBiases biases_;
  MagneticField field_;
  std::vector<double> phases_s_;
  std::shared_ptr<const FloorRenderer> floor_;  // floor_camera scenarios
};

}  // namespace luxloc::sim
