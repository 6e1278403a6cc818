#pragma once
// Named simulation scenarios: the room and its LED map, the camera, the device height and
// the trajectory, with a default duration (docs/SIMULATOR.md "Scenarios").
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/common/session_config.hpp"
#include "core/sim/trajectory.hpp"
#include "core/sim/uwb_synth.hpp"
#include "core/sim/walk_trajectory.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc::sim {

struct Scenario {
  std::string name;
  std::string description;
  double duration_s = 90.0;
  double room_x_m = 8.0, room_y_m = 6.0;  // floor extent [0, room_x] x [0, room_y]
  double device_height_m = 1.0;           // nominal height of the device above the floor
  LedMap map;
  CameraModel camera;
  std::shared_ptr<const Trajectory> trajectory;
  // The pedestrian scenarios' walk (its path, height and walker), so `sim --walker random`
  // can walk the same path with another walker (walker_population.hpp); empty otherwise.
  std::optional<WalkOptions> walk;
  bool frames = true;               // false: the session has no camera frames (UWB, IMU, truth)
  bool floor_camera = false;        // frames show the textured floor (FloorRenderer), not LEDs
  bool start_fix = false;           // fixes.csv with the true start position (relative navigation)
  std::vector<UwbAnchor> anchors;   // UWB anchors: non-empty -> uwb.csv and session.yaml anchors
  UwbSimOptions uwb;
  // The IMU this scenario is simulated with (imu_grade.hpp) and its magnetic disturbance
  // (mag_disturbance.hpp); `luxloc sim --imu-grade / --mag-disturbance` override them.
  std::string imu_grade = "default";
  std::string mag_disturbance = "none";
};

// "walk" (the default), "static", "square", "dense", "uwb", "floor", "drone", "robot", "floorplan".
std::vector<std::string> scenario_names();
// Throws std::invalid_argument naming the valid scenarios for an unknown name.
Scenario make_scenario(const std::string& name);

// The scenarios' shared pieces, for tests and other tools.
CameraModel default_sim_camera();  // 640x480, f 460 px, k1 -0.05, 30 us rows, 100 us exposure, looking up
CameraModel floor_sim_camera();    // 320x240, f 230 px, no distortion, looking down, image top = forward
// 4 x 3 grid, x = 1,3,5,7, y = 1,3,5, z = 3 m, 0.20 m discs, 1000 + 300 i Hz (ids 1..12).
LedMap default_led_grid();

}  // namespace luxloc::sim
