#pragma once
// session.yaml (SPEC.md "Session folder"): an optional OpenCV FileStorage YAML file with
// session-wide settings. Keys read (all optional; unknown keys are ignored):
//   device_height_m: 1.0                         nominal device height above the floor (m, >= 0)
//   anchors:                                     UWB anchors, world frame (m)
//      - { id: 1, x: 0.0, y: 0.0, z: 2.5 }
//   imu: imu.csv        frames: frames.csv       sensor file names, relative to the session
//   uwb: uwb.csv        fixes: fixes.csv         folder (or absolute), where they differ
//   odom: odom.csv      groundtruth: groundtruth.csv     from SPEC's defaults
//   ledmap: ledmap.yaml camera: camera.yaml
//   sensor_limits: { acc_max_g: 16, gyro_max_dps: 2000, mag_max_ut: 1000, range_max_m: 200 }
//                                                plausible ranges; a sample beyond them is
//                                                skipped as "out of range" (sensor_limits.hpp)
#include <string>
#include <vector>

#include "core/common/session_config.hpp"

namespace luxloc {

// Throws InputError naming the file and the key on unusable content (syntax error, wrong
// type, anchor with a missing field or duplicate id, negative height).
SessionConfig load_session_config(const std::string& path);
// Writes every key above (what load_session_config reads back).
void save_session_config(const SessionConfig& config, const std::string& path);

// Reads an `anchors` sequence from any OpenCV YAML file (session.yaml, or a map file that
// carries one); empty when the key is absent. Throws InputError like load_session_config.
std::vector<UwbAnchor> load_anchors(const std::string& path);

}  // namespace luxloc
