#pragma once
// The simulator's ground truth as the checking tools read it back: groundtruth.csv (pose
// with attitude), sim_truth.yaml's blackouts, and the LEDs each frame really shows
// (re-rendered from the true pose). Used by `vlc --check-ids` and `run --check-associations`.
#include <Eigen/Core>
#include <filesystem>
#include <random>
#include <utility>
#include <vector>

#include "core/sim/frame_renderer.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/id_check.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc::app {

struct SimTruthRow {
  double t = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double yaw = 0, roll = 0, pitch = 0;
};

struct SimTruth {
  std::vector<SimTruthRow> rows;
  bool has_tilt = false;  // roll, pitch columns (the simulator writes them)
  bool has_z = false;

  // Linear interpolation (yaw across the wrap); false outside the file's time span.
  bool at(double t, Eigen::Matrix3d& R, Eigen::Vector3d& p) const;
};

// groundtruth.csv (t, x, y[, z, yaw, roll, pitch]); rows out of time order are skipped.
SimTruth read_truth(const std::filesystem::path& path);
// sim_truth.yaml's blackouts as (start_s, duration_s); none when the file is absent.
std::vector<std::pair<double, double>> read_blackouts(const std::filesystem::path& sim_truth);
// The LEDs a frame at time t really shows: the renderer run on the true pose at each row's
// time (noise-free options), with each LED's frequency class.
std::vector<TrueLedBlob> true_led_blobs(const SimTruth& truth, const CameraModel& camera, const LedMap& map, double t,
                                        const sim::RenderOptions& options, std::mt19937_64& rng);

}  // namespace luxloc::app
