#pragma once
// LED map calibration from a recorded session (issue: "LED map calibration"):
//   refine: LED positions by least squares over every bearing ray towards each LED from
//           known device poses (core/vlc/led_triangulation.hpp), per-LED residuals;
//   check:  LEDs never seen, frequencies that drift from the map or cannot be told apart by
//           the decoder at this camera's row time (with the spacing it needs), and LEDs whose
//           observed position disagrees with the map.
// The app layer decodes the frames (StripeDecoder) into sightings and builds the pose track
// (poses file + IMU attitude); this file does the estimation only.
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/common/time.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_observation.hpp"

namespace luxloc {

// One decoded LED blob at its observation time (frame start + row x row time + half the
// exposure: when its rows were exposed).
struct TimedLedSighting {
  int led_index = -1;  // into the map
  TimeNs t_obs = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double freq_hz = 0.0;
  double freq_sigma_hz = 0.0;
};

// Sightings of one frame's decoded observations (accepted ones only).
std::vector<TimedLedSighting> sightings_of_frame(TimeNs t_frame, const std::vector<LedObservation>& obs,
                                            const CameraModel& camera);

struct DevicePose {
  Eigen::Quaterniond q_BtoW = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_BinW = Eigen::Vector3d::Zero();
};
// The device pose at a time, or nothing (outside the known poses).
using PoseLookup = std::function<std::optional<DevicePose>(TimeNs)>;

// Poses at known times (sorted), interpolated: linear in position, slerp in attitude.
class PoseTrack {
 public:
  void add(TimeNs t, const DevicePose& p);
  std::optional<DevicePose> at(TimeNs t) const;
  std::size_t size() const { return t_.size(); }

 private:
  std::vector<TimeNs> t_;
  std::vector<DevicePose> poses_;
};

struct LedRefineOptions {
  bool fix_z = false;             // keep each LED's map height (known ceiling)
  std::size_t min_sightings = 5;  // fewer: the LED keeps its map position (reported)
  double huber_m = 0.02;
};

struct LedRefinement {
  int id = 0;
  std::size_t sightings = 0;
  bool refined = false;
  Eigen::Vector3d before = Eigen::Vector3d::Zero(), after = Eigen::Vector3d::Zero();
  double rms_m = 0.0;  // rms distance of the bearing rays from the refined position
};

struct LedRefineReport {
  LedMap map;  // the corrected map
  std::vector<LedRefinement> leds;
};

LedRefineReport refine_led_map(const LedMap& map, const CameraModel& camera, const std::vector<TimedLedSighting>& sightings,
                               const PoseLookup& pose_at, const LedRefineOptions& options = {});

struct LedCheckOptions {
  double position_threshold_m = 0.10;  // observed vs map position
  double drift_fraction = 0.5;         // mean frequency off by more than this x the decoder tolerance
  double rel_tolerance = 0.05;         // the decoder's match tolerance (StripeDecoderOptions)
  double min_relative_separation = 0.02;  // never less than this (LedMapOptions)
  std::size_t min_sightings = 5;
};

struct LedFrequencyStats {
  int id = 0;
  std::size_t sightings = 0;
  double map_hz = 0.0, mean_hz = 0.0, std_hz = 0.0;
  bool drifts = false;
};

struct LedCollision {
  int id_a = 0, id_b = 0;
  double gap_hz = 0.0;
  double needed_hz = 0.0;  // spacing the decoder needs at this row time
};

struct LedMisplacement {
  int id = 0;
  double distance_m = 0.0;
  Eigen::Vector3d observed = Eigen::Vector3d::Zero();
};

struct LedCheckReport {
  std::vector<int> never_seen;
  std::vector<LedFrequencyStats> frequencies;  // per LED of the map
  double relative_sigma = 0.0;                 // decoder frequency noise (median sigma / f)
  double needed_relative_spacing = 0.0;
  std::vector<LedCollision> collisions;
  std::vector<LedMisplacement> misplaced;  // only with poses
  bool checked_positions = false;
};

LedCheckReport check_led_map(const LedMap& map, const CameraModel& camera, const std::vector<TimedLedSighting>& sightings,
                             const PoseLookup* pose_at, const LedCheckOptions& options = {});

}  // namespace luxloc
