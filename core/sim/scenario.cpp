#include "core/sim/scenario.hpp"

#include <limits>
#include <stdexcept>

#include "core/sim/flight_trajectory.hpp"
#include "core/sim/walk_trajectory.hpp"
#include "core/vlc/frequency_plan.hpp"
#include "core/vlc/led_visibility.hpp"

namespace luxloc::sim {

CameraModel default_sim_camera() {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 460.0;
  c.cx = 320.0;
  c.cy = 240.0;
  c.dist = {-0.05, 0.0, 0.0, 0.0, 0.0};
  c.row_time_s = 30e-6;
  c.exposure_s = 100e-6;
  // Looking up: camera x = body -y (right), camera y = body +x (forward), camera z = body z
  // (up); columns of R_CtoB are the camera axes in the body frame (SPEC R_body_camera).
  c.R_CtoB << 0, 1, 0,  //
      -1, 0, 0,         //
      0, 0, 1;
  c.p_CinB.setZero();
  return c;
}

CameraModel floor_sim_camera() {
  CameraModel c;
  c.width = 320;
  c.height = 240;
  c.fx = c.fy = 230.0;
  c.cx = 160.0;
  c.cy = 120.0;
  c.dist = {0.0, 0.0, 0.0, 0.0, 0.0};
  c.exposure_s = 2e-3;
  // Looking down: camera x (image right) = body -y, camera y (image down) = body -x
  // (image top = forward), camera z = body -z.
  c.R_CtoB << 0, -1, 0,  //
      -1, 0, 0,          //
      0, 0, -1;
  c.p_CinB.setZero();
  return c;
}

LedMap default_led_grid() {
  std::vector<Led> leds;
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) {
      const int i = iy * 4 + ix;
      Led l;
      l.id = i + 1;
      l.freq_hz = 1000.0 + 300.0 * i;
      l.p_inW = {1.0 + 2.0 * ix, 1.0 + 2.0 * iy, 3.0};
      l.duty = 0.5;
      l.half_power_angle_deg = 60.0;
      l.power = 1.0;
      l.diameter_m = 0.20;
      leds.push_back(l);
    }
  return LedMap(std::move(leds), "sim:default_led_grid");
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Scenario base(const std::string& name, const std::string& description, double duration_s) {
  Scenario s;
  s.name = name;
  s.description = description;
  s.duration_s = duration_s;
  s.map = default_led_grid();
  s.camera = default_sim_camera();
  return s;
}

Scenario walk() {
  Scenario s = base("walk",
                    "a person walks a 24 m loop under all 12 LEDs of an 8 m x 6 m room, with two brief stops",
                    90.0);
  WalkOptions w;
  // All turns 90 deg; every LED of the grid lies on the loop, 1 m from the walls.
  w.waypoints = {{1, 1}, {7, 1}, {7, 5}, {5, 5}, {5, 3}, {3, 3}, {3, 5}, {1, 5}};
  w.corner_sigma_m = 0.5;
  w.start_u_m = 2.0;  // (3, 1), under LED 2, heading east
  w.height_m = s.device_height_m;
  w.walking = {{2.0, 31.0}, {33.0, 61.0}, {63.0, kInf}};  // stand 2 s first, then stop twice for 2 s
  s.trajectory = std::make_shared<WalkTrajectory>(w);
  s.walk = w;
  return s;
}

Scenario square() {
  Scenario s = base("square", "a slow walk (0.6 m/s) around a 4 m x 4 m square", 60.0);
  WalkOptions w;
  w.waypoints = {{2, 1}, {6, 1}, {6, 5}, {2, 5}};
  w.corner_sigma_m = 0.4;
  w.start_u_m = 1.0;  // (3, 1), under LED 2, heading east
  w.height_m = s.device_height_m;
  w.walking = {{2.0, kInf}};
  w.gait.speed_mps = 0.6;
  w.gait.step_hz = 1.4;
  w.gait.bounce_m = 0.008;
  s.trajectory = std::make_shared<WalkTrajectory>(w);
  s.walk = w;
  return s;
}

// The walk under a higher ceiling (3.6 m: 2.6 m above the device) with a denser grid
// (1.5 m, centred in the room) of larger discs (0.40 m, ~70 px across): the camera sees a
// 3.6 m x 2.7 m patch of the ceiling, so 1-4 whole LEDs (up to 6 near the middle of the
// room) are in view at once, where the walk shows one: enough for the RSS fix (>= 3) and
// the multi-LED decoder check. The disc size follows the room-design rule of docs/VLC.md:
// the lowest frequency's stripe period (1000 Hz: 33 rows at 30 us) fits twice into a blob.
// Same LED ids and frequencies as every other scenario.
Scenario dense() {
  Scenario s = walk();
  s.name = "dense";
  s.description = "the walk under a 3.6 m ceiling, 0.40 m LEDs 1.5 m apart: 1-4 whole LEDs in view at once";
  std::vector<Led> leds = s.map.leds();
  for (std::size_t i = 0; i < leds.size(); ++i) {
    // The 4 x 3 grid, 1.5 m apart, centred in the room: x = 1.75 .. 6.25, y = 1.5 .. 4.5.
    leds[i].p_inW = {1.75 + 1.5 * static_cast<double>(i % 4), 1.5 + 1.5 * static_cast<double>(i / 4), 3.6};
    leds[i].diameter_m = 0.40;
  }
  s.map = LedMap(std::move(leds), "sim:dense_led_grid");
  return s;
}

Scenario still() {
  Scenario s = base("static", "standing still at (3, 2) facing 0.5 rad, LEDs 2 and 6 in view", 30.0);
  s.trajectory = std::make_shared<StaticTrajectory>(Eigen::Vector3d(3.0, 2.0, s.device_height_m), 0.5);
  return s;
}

// SEEDS.md B's setting: one UWB base station measuring time of flight and angle of
// arrival, 5 % non-line-of-sight outliers, a 120 s walk; no camera frames.
Scenario uwb() {
  Scenario s = base("uwb",
                    "a 120 s walk around one ceiling UWB base station at (4, 3, 2.8) giving TOF range + AOA at 10 Hz, "
                    "5 % NLOS outliers; no camera",
                    120.0);
  s.frames = false;
  s.anchors = {UwbAnchor{1, Eigen::Vector3d(4.0, 3.0, 2.8)}};
  WalkOptions w;
  w.waypoints = {{1, 1}, {7, 1}, {7, 5}, {5, 5}, {5, 4}, {3, 4}, {3, 5}, {1, 5}};
  w.corner_sigma_m = 0.5;
  w.start_u_m = 2.0;  // (3, 1), heading east
  w.height_m = s.device_height_m;
  w.walking = {{2.0, 41.0}, {43.0, 81.0}, {83.0, kInf}};
  s.trajectory = std::make_shared<WalkTrajectory>(w);
  s.walk = w;
  return s;
}

// SEEDS.md C's setting, on wheels: a camera looking down at a textured floor from 1 m,
// carried smoothly (no gait sway, so the flat-floor odometry model holds) around a loop.
Scenario floor() {
  Scenario s = base("floor",
                    "a 60 s smooth ride (0.8 m/s) with a downward camera over a textured floor, 320x240 at 30 fps; "
                    "no LEDs; the start position in fixes.csv",
                    60.0);
  s.map = LedMap();
  s.camera = floor_sim_camera();
  s.floor_camera = true;
  s.start_fix = true;
  WalkOptions w;
  w.waypoints = {{1, 1}, {7, 1}, {7, 5}, {4, 5}, {4, 3}, {1, 3}};
  w.corner_sigma_m = 0.6;
  w.start_u_m = 1.0;
  w.height_m = s.device_height_m;
  w.walking = {{2.0, kInf}};
  w.gait.speed_mps = 0.8;
  w.gait.speed_modulation = 0.0;
  w.gait.bounce_m = 0.0;
  w.gait.roll_sway_rad = w.gait.pitch_sway_rad = w.gait.yaw_sway_rad = 0.0;
  s.trajectory = std::make_shared<WalkTrajectory>(w);
  return s;
}

// Ranges as a DW1000 kit delivers them (issue 16): range only, 10 Hz per anchor taking
// turns, 5 cm noise (the DW1000 data sheet's ~10 cm 2-sigma LOS figure), per-anchor bias
// drawn in -0.5 .. +0.1 m (uncalibrated antenna delays, mostly short: the arena
// measured -0.02 .. -0.44 m), 2 % sporadic NLOS, and one anchor behind an obstacle for a
// third of the run.
UwbSimOptions radio_ranges(int blocked_anchor, double duration_s) {
  UwbSimOptions u;
  u.with_aoa = false;
  u.stagger = true;
  u.range_sigma_m = 0.05;
  u.nlos_probability = 0.02;
  u.bias_min_m = -0.5;
  u.bias_max_m = 0.1;
  u.blocked_anchor = blocked_anchor;
  u.blocked_from_s = duration_s / 3.0;
  u.blocked_to_s = 2.0 * duration_s / 3.0;
  return u;
}

// A small quadrotor in an 8 m x 6 m arena: 8 anchors on the walls, alternately low
// (0.3 m) and high (2.6 m), a 0.8 m/s loop with the height swinging 0.5 .. 1.7 m, and rotor
// vibration: four tones of 80-260 Hz (hover at ~150 Hz blade pass; 1.5 m/s^2 and
// 0.1 rad/s each, a soft-mounted flight controller's order of magnitude).
Scenario drone() {
  Scenario s = base("drone",
                    "a 60 s quadrotor flight around an 8 m x 6 m arena, height 0.5-1.7 m, rotor vibration on the IMU, "
                    "8 UWB anchors at 0.3 / 2.6 m with per-anchor bias, anchor 3 in NLOS for the middle third; no camera",
                    60.0);
  s.frames = false;
  s.device_height_m = 1.1;
  for (int i = 0; i < 8; ++i) {
    // Corners and wall midpoints of the room, 0.2 m inside it.
    static constexpr double xy[8][2] = {{0.2, 0.2}, {4.0, 0.2}, {7.8, 0.2}, {7.8, 3.0},
                                        {7.8, 5.8}, {4.0, 5.8}, {0.2, 5.8}, {0.2, 3.0}};
    s.anchors.push_back(UwbAnchor{i + 1, Eigen::Vector3d(xy[i][0], xy[i][1], i % 2 == 0 ? 0.3 : 2.6)});
  }
  s.uwb = radio_ranges(3, s.duration_s);
  FlightOptions f;
  f.waypoints = {{1.5, 1.5}, {6.5, 1.5}, {6.5, 4.5}, {1.5, 4.5}};
  f.start_u_m = 1.0;
  f.speed_mps = 0.8;
  f.height_m = 1.1;
  f.height_amplitude_m = 0.6;
  f.height_period_s = 20.0;
  f.vibration = {{83.0, 1.5, 0.1}, {151.0, 1.5, 0.1}, {197.0, 1.5, 0.1}, {263.0, 1.5, 0.1}};
  s.trajectory = std::make_shared<FlightTrajectory>(f);
  return s;
}

// A ground robot / trolley: no gait, smooth turns, the device at a constant 0.5 m, motor
// vibration (two tones of 60 / 120 Hz, 0.4 m/s^2, 0.02 rad/s: wheels on a hard floor),
// 6 anchors at 0.5 .. 2.5 m with per-anchor bias, anchor 2 in NLOS for the middle third.
Scenario robot() {
  Scenario s = base("robot",
                    "a 90 s ground-robot loop (0.6 m/s) at a constant 0.5 m, motor vibration on the IMU, 6 UWB anchors "
                    "with per-anchor bias, anchor 2 in NLOS for the middle third; no camera",
                    90.0);
  s.frames = false;
  s.device_height_m = 0.5;
  s.anchors = {UwbAnchor{1, {0.2, 0.2, 2.5}}, UwbAnchor{2, {4.0, 0.2, 0.5}}, UwbAnchor{3, {7.8, 0.2, 2.0}},
               UwbAnchor{4, {7.8, 5.8, 2.5}}, UwbAnchor{5, {4.0, 5.8, 1.0}}, UwbAnchor{6, {0.2, 5.8, 2.0}}};
  s.uwb = radio_ranges(2, s.duration_s);
  FlightOptions f;
  f.waypoints = {{1, 1}, {7, 1}, {7, 5}, {4, 5}, {4, 3}, {1, 3}};
  f.corner_sigma_m = 0.6;
  f.start_u_m = 1.0;
  f.speed_mps = 0.6;
  f.height_m = 0.5;
  f.vibration = {{60.0, 0.4, 0.02}, {120.0, 0.4, 0.02}};
  s.trajectory = std::make_shared<FlightTrajectory>(f);
  return s;
}

// Issue 14's building-scale VLC: a 60 m x 30 m office floor, 450 ceiling LEDs on a 2 m grid
// sharing 12 frequencies (frequency reuse), planned as `luxloc calib ledmap plan` would for
// this camera (frequency_plan.hpp: the band from the camera, DSatur + random recolouring for
// the largest aperiodic reuse distance). The walk follows the central corridor, goes into
// rooms on both sides and back, about 170 m a lap (~2 min), with two brief stops.
Scenario floorplan() {
  Scenario s = base("floorplan",
                    "a 10-minute walk through a 60 m x 30 m office floor: corridor and rooms under 450 LEDs on a 2 m "
                    "grid that share 12 frequencies",
                    600.0);
  s.room_x_m = 60.0;
  s.room_y_m = 30.0;
  const double ceiling_z = 3.0, diameter = 0.20, max_tilt = 15.0 * 3.14159265358979323846 / 180.0;
  std::vector<Eigen::Vector2d> xy;
  for (int iy = 0; iy < 15; ++iy)
    for (int ix = 0; ix < 30; ++ix) xy.emplace_back(1.0 + 2.0 * ix, 1.0 + 2.0 * iy);
  // The planner's conflict distance: co-visible within 15 deg of level, plus the disc and
  // 0.25 m (calib ledmap plan's defaults).
  const double dz = ceiling_z - s.device_height_m;
  const double conflict = co_visibility_distance_m(s.camera, dz, max_tilt) + diameter + 0.25;
  FrequencyPlanOptions po;
  po.classes = 12;
  po.seed = 14;  // fixed: the scenario is one floor, the same every run
  const FrequencyPlan plan = plan_frequency_classes(xy, conflict, po);
  const std::vector<double> freqs = spread_frequencies(frequency_band(s.camera, dz, diameter), 12);
  std::vector<Led> leds;
  for (std::size_t i = 0; i < xy.size(); ++i) {
    Led l;
    l.id = static_cast<int>(i) + 1;
    l.freq_hz = freqs[static_cast<std::size_t>(plan.class_of[i])];
    l.p_inW = {xy[i].x(), xy[i].y(), ceiling_z};
    l.diameter_m = diameter;
    leds.push_back(l);
  }
  s.map = LedMap(std::move(leds), "sim:floorplan");
  WalkOptions w;
  // Corridor along y = 15; a room to the north (x 28-38), the east wing, a room to the south
  // (x 20-40) reached from both ends, back west along y = 4 and north to the corridor.
  w.waypoints = {{3, 15},  {27, 15}, {27, 25}, {37, 25}, {37, 15}, {57, 15}, {57, 5},
                 {41, 5},  {41, 10}, {21, 10}, {21, 5},  {3, 5}};
  w.corner_sigma_m = 0.5;
  w.start_u_m = 2.0;  // (5, 15), under LED (5, 15), heading east
  w.height_m = s.device_height_m;
  w.walking = {{2.0, 200.0}, {203.0, 400.0}, {402.0, kInf}};  // stand 2 s first, then stop twice
  s.trajectory = std::make_shared<WalkTrajectory>(w);
  s.walk = w;
  return s;
}

}  // namespace

std::vector<std::string> scenario_names() {
  return {"walk", "static", "square", "dense", "uwb", "floor", "drone", "robot", "floorplan"};
}

Scenario make_scenario(const std::string& name) {
  if (name == "walk") return walk();
  if (name == "static") return still();
  if (name == "square") return square();
  if (name == "dense") return dense();
  if (name == "uwb") return uwb();
  if (name == "floor") return floor();
  if (name == "drone") return drone();
  if (name == "robot") return robot();
  if (name == "floorplan") return floorplan();
  std::string valid;
  for (const std::string& n : scenario_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown scenario '" + name + "' (valid: " + valid + ")");
}

}  // namespace luxloc::sim
