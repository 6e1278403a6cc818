#pragma once
// Opens a recorded session folder (SPEC.md "Session folder") for file playback: reads the
// optional session.yaml, ledmap.yaml and camera.yaml, and makes one streaming Source per
// sensor file present (order: imu, frames, uwb, fixes, odom).
#include <filesystem>
#include <optional>
#include <vector>

#include "core/common/session_config.hpp"
#include "core/pipeline/source.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc {

struct PlaybackOptions {
  std::filesystem::path map_path;     // `--map`: overrides the session's LED map (must exist)
  std::filesystem::path camera_path;  // `--camera`: overrides the session's camera.yaml (must exist)
  LedMapOptions map_options;
  bool check_frame_size = true;  // drop frames whose size differs from the camera model
};

struct PlaybackSession {
  std::filesystem::path dir;
  SessionConfig config;                 // session.yaml, defaults when absent
  std::optional<LedMap> map;            // LED map if present
  std::optional<CameraModel> camera;    // camera model if present
  std::optional<std::filesystem::path> groundtruth;  // groundtruth.csv if present (for eval)
  std::vector<SourcePtr> sources;       // one per sensor file present
};

// Throws InputError (exit 2) when: `dir` is missing or not a folder; it holds no sensor
// file; session.yaml / the LED map / the camera file is unreadable or invalid (message
// names the file and field); a file named explicitly (session.yaml key, --map, --camera)
// does not exist; a sensor CSV lacks a required column. Bad data rows are not errors here:
// the sources skip and count them while streaming.
// UWB anchors come from session.yaml's `anchors`, else from an `anchors` key in the map file.
PlaybackSession open_playback(const std::filesystem::path& dir, const PlaybackOptions& options = {});

}  // namespace luxloc
