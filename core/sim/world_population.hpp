#pragma once
// A population of cameras and ceilings (issue 12, part 1): `luxloc sim --world random` puts
// the scenario's walk under a camera mode and an LED layout drawn from the session's seed,
// and `--camera-mode` under one camera mode of the user's choice. Drawn per session and
// written to sim_truth.yaml (`world:`), so a failing session can be reproduced:
//   camera: 640x480, 800x600, 1280x720 or 1920x1080; row time 15-45 us (at most 90 % of the
//     frame period over the rows: a 1080p sensor at 30 fps reads a row in <= 28 us);
//     exposure 50-300 us; horizontal field of view 50-95 deg (narrow to wide lenses), barrel
//     distortion growing with it (k1 -0.05 .. -0.25, less where the corner would fold);
//   ceiling 2.4-4.0 m; LEDs on a grid 2-4 m apart over the room, or irregular (each light
//     moved by up to a quarter of the spacing); disc 0.15-0.40 m;
//   frequencies planned for that camera as `luxloc calib ledmap plan` would (frequency_plan.hpp:
//     the band from the camera and the smallest blob, spread geometrically), one class per
//     LED where the band holds them, reused beyond the co-visibility distance where not.
// A deployment is designed for its camera: where the drawn disc leaves the band too narrow
// for the lights (short rows, long exposure, a high ceiling), the disc grows (to 0.6 m, a
// panel light), then the exposure shortens, as an installer would.
#include <cstdint>
#include <string>
#include <vector>

#include "core/sim/scenario.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/frequency_plan.hpp"

namespace luxloc::sim {

struct CameraMode {
  int width = 640, height = 480;
  double row_time_s = 30e-6;
  double exposure_s = 100e-6;
  double hfov_deg = 69.6;  // default_sim_camera(): f 460 px over 640 columns
};

// "WxH:ROW_US:EXPOSURE_US[:HFOV_DEG]", e.g. "1280x720:45:200:70"; throws
// std::invalid_argument naming the part that is wrong.
CameraMode parse_camera_mode(const std::string& text);
// The up-looking camera of default_sim_camera() in that mode: f from the field of view,
// the principal point at the centre, k1 from -0.05 (50 deg) to -0.25 (95 deg), kept monotonic.
CameraModel camera_for_mode(const CameraMode& mode);

struct WorldDraw {
  CameraMode camera;
  std::string layout = "grid";  // grid | irregular
  double spacing_m = 2.0;
  double ceiling_m = 3.0;
  double led_diameter_m = 0.2;
};

inline constexpr const char* kWorldNames[] = {"default", "random"};

// The world of session `seed` (camera frames at `fps`).
WorldDraw draw_world(std::uint64_t seed, double fps);

// What apply_world / plan_for_camera did to the map (for sim_truth.yaml and the report).
struct WorldPlan {
  double led_diameter_m = 0.0;
  double exposure_s = 0.0;  // the camera's, after any shortening
  FrequencyBand band;
  int leds = 0, classes = 0;
  double min_reuse_distance_m = 0.0;  // infinity: every LED its own class
};

// The scenario's room lit by w's layout and filmed by w's camera; frequencies planned for it.
// Throws std::invalid_argument for a scenario whose frames do not look at the ceiling.
WorldPlan apply_world(Scenario& s, const WorldDraw& w, std::uint64_t seed);
// The scenario's own LED positions under camera mode `mode`, frequencies re-planned for it
// (`sim --camera-mode`).
WorldPlan apply_camera_mode(Scenario& s, const CameraMode& mode, std::uint64_t seed);

}  // namespace luxloc::sim
