#include "core/sim/world_population.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "core/common/text_split.hpp"
#include "core/sim/seeding.hpp"
#include "core/vlc/led_visibility.hpp"

namespace luxloc::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Planner defaults of `luxloc calib ledmap plan` (docs/VLC.md): a camera tilted up to 15 deg,
// 0.25 m margin, at most 12 classes where lights must share frequencies.
constexpr double kMaxTiltRad = 15.0 * kDeg;
constexpr double kMarginM = 0.25;
constexpr int kMaxReuseClasses = 12;
constexpr double kMaxDiameterM = 0.6;  // a 60 cm panel light
constexpr double kMinExposureS = 20e-6;

double parse_number(const std::string& s, const char* what) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (s.empty() || used != s.size() || !std::isfinite(v))
    throw std::invalid_argument(std::string(what) + ": not a number: '" + s + "'");
  return v;
}

// Frequencies for the lights at p_inW filmed by the scenario's camera: one class per
// light where the band holds them, else the planner's reuse. Grows the disc, then shortens
// the exposure, until the band holds the classes needed.
WorldPlan plan_lights(Scenario& s, const std::vector<Eigen::Vector3d>& p_inW, double diameter_m, std::uint64_t seed) {
  WorldPlan plan;
  const int n = static_cast<int>(p_inW.size());
  double top = -std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector2d> xy;
  for (const Eigen::Vector3d& p : p_inW) {
    top = std::max(top, p.z());
    xy.emplace_back(p.x(), p.y());
  }
  const double dz = top - s.device_height_m;
  if (!(dz > 0.3)) throw std::invalid_argument("the ceiling is not above the device");
  CameraModel& cam = s.camera;
  double diameter = diameter_m;
  FrequencyPlan colouring;
  // Terminates: the disc reaches kMaxDiameterM and the exposure kMinExposureS in finitely
  // many 15 % steps, then the plan throws.
  while (true) {
    plan.band = frequency_band(cam, dz, diameter);
    if (plan.band.capacity >= n) {
      colouring.class_of.resize(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i) colouring.class_of[static_cast<std::size_t>(i)] = i;
      colouring.classes = n;
      colouring.min_reuse_distance_m = std::numeric_limits<double>::infinity();
      break;
    }
    const double conflict = co_visibility_distance_m(cam, dz, kMaxTiltRad) + diameter + kMarginM;
    FrequencyPlanOptions po;
    po.seed = seed;
    po.classes = std::min(plan.band.capacity, kMaxReuseClasses);
    if (po.classes >= 2) {
      try {
        colouring = plan_frequency_classes(xy, conflict, po);
        break;
      } catch (const std::invalid_argument&) {
        // more classes needed than the band holds: widen the band below
      }
    }
    if (diameter < kMaxDiameterM) {
      diameter = std::min(kMaxDiameterM, diameter * 1.15);
    } else if (cam.exposure_s > kMinExposureS) {
      cam.exposure_s = std::max(kMinExposureS, cam.exposure_s / 1.15);
    } else {
      throw std::invalid_argument("no frequency plan fits this camera and ceiling");
    }
  }
  // Classes in a seeded order over the band, so neighbouring lights do not get neighbouring
  // frequencies by construction.
  std::vector<double> freqs = spread_frequencies(plan.band, colouring.classes);
  std::mt19937_64 rng = make_rng(seed, RandomStream::world, 1);
  std::shuffle(freqs.begin(), freqs.end(), rng);
  std::vector<Led> leds;
  for (int i = 0; i < n; ++i) {
    Led l;
    l.id = i + 1;
    l.freq_hz = freqs[static_cast<std::size_t>(colouring.class_of[static_cast<std::size_t>(i)])];
    l.p_inW = p_inW[static_cast<std::size_t>(i)];
    l.diameter_m = diameter;
    leds.push_back(l);
  }
  s.map = LedMap(std::move(leds), "sim:world");
  plan.led_diameter_m = diameter;
  plan.exposure_s = cam.exposure_s;
  plan.leds = n;
  plan.classes = colouring.classes;
  plan.min_reuse_distance_m = colouring.min_reuse_distance_m;
  return plan;
}

void require_ceiling_camera(const Scenario& s) {
  if (!s.frames || s.floor_camera) throw std::invalid_argument("scenario '" + s.name + "' has no up-looking camera");
}

}  // namespace

CameraMode parse_camera_mode(const std::string& text) {
  const std::vector<std::string> parts = split_text(text, ':');
  if (parts.size() != 3 && parts.size() != 4)
    throw std::invalid_argument("expected WxH:ROW_US:EXPOSURE_US[:HFOV_DEG], got '" + text + "'");
  const std::vector<std::string> wh = split_text(parts[0], 'x');
  if (wh.size() != 2) throw std::invalid_argument("size: expected WxH (e.g. 1280x720), got '" + parts[0] + "'");
  CameraMode m;
  const double w = parse_number(wh[0], "width"), h = parse_number(wh[1], "height");
  if (w != std::floor(w) || h != std::floor(h) || w < 64 || h < 48 || w > 8192 || h > 8192)
    throw std::invalid_argument("size: width 64-8192 and height 48-8192 whole pixels, got '" + parts[0] + "'");
  m.width = static_cast<int>(w);
  m.height = static_cast<int>(h);
  const double row_us = parse_number(parts[1], "row time");
  if (!CameraModel::plausible_row_time_us(row_us))
    throw std::invalid_argument("row time: " + parts[1] + " us is outside 1-200 us");
  const double exp_us = parse_number(parts[2], "exposure");
  if (!(exp_us >= 1.0 && exp_us <= 1e5)) throw std::invalid_argument("exposure: " + parts[2] + " us is outside 1-100000 us");
  m.row_time_s = row_us * 1e-6;
  m.exposure_s = exp_us * 1e-6;
  if (parts.size() == 4) {
    m.hfov_deg = parse_number(parts[3], "field of view");
    if (!(m.hfov_deg >= 20.0 && m.hfov_deg <= 120.0))
      throw std::invalid_argument("field of view: " + parts[3] + " deg is outside 20-120 deg");
  }
  return m;
}

CameraModel camera_for_mode(const CameraMode& mode) {
  CameraModel c = default_sim_camera();
  c.width = mode.width;
  c.height = mode.height;
  c.fx = c.fy = 0.5 * mode.width / std::tan(0.5 * mode.hfov_deg * kDeg);
  c.cx = 0.5 * mode.width;
  c.cy = 0.5 * mode.height;
  // Barrel distortion grows with the field of view: the default camera's -0.05 at 50 deg,
  // -0.25 at 95 deg (a wide webcam lens), linear in between; but the radial map
  // r_d = r (1 + k1 r^2) must keep growing out to the ray that lands on the image corner
  // (slope 1 + 3 k1 r^2 > 0), or the lens would fold rays from outside the view back into the
  // image. k1 >= -0.1 / r_dc^2 (r_dc: the corner's distorted normalised radius) puts that ray
  // at r = 1.155 r_dc, where the slope is still 0.6.
  const double r2_corner = (0.25 * mode.width * mode.width + 0.25 * mode.height * mode.height) / (c.fx * c.fx);
  const double k1 = -0.05 - 0.2 * std::clamp((mode.hfov_deg - 50.0) / 45.0, 0.0, 1.0);
  c.dist = {std::max(k1, -0.1 / r2_corner), 0.0, 0.0, 0.0, 0.0};
  c.row_time_s = mode.row_time_s;
  c.exposure_s = mode.exposure_s;
  return c;
}

WorldDraw draw_world(std::uint64_t seed, double fps) {
  std::mt19937_64 rng = make_rng(seed, RandomStream::world);
  const auto uniform = [&rng](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  static constexpr int kSizes[][2] = {{640, 480}, {800, 600}, {1280, 720}, {1920, 1080}};
  WorldDraw w;
  const auto& size = kSizes[std::uniform_int_distribution<int>(0, 3)(rng)];
  w.camera.width = size[0];
  w.camera.height = size[1];
  // The rows are read within the frame period (90 % of it: the vertical blanking).
  const double max_row_s = std::min(45e-6, 0.9 / (std::max(fps, 1.0) * w.camera.height));
  w.camera.row_time_s = uniform(15e-6, std::max(15e-6, max_row_s));
  w.camera.exposure_s = uniform(50e-6, 300e-6);
  w.camera.hfov_deg = uniform(50.0, 95.0);
  w.layout = uniform(0.0, 1.0) < 0.5 ? "grid" : "irregular";
  w.spacing_m = uniform(2.0, 4.0);
  w.ceiling_m = uniform(2.4, 4.0);
  w.led_diameter_m = uniform(0.15, 0.40);
  return w;
}

WorldPlan apply_world(Scenario& s, const WorldDraw& w, std::uint64_t seed) {
  require_ceiling_camera(s);
  s.camera = camera_for_mode(w.camera);
  // Grid over the room, centred, ~spacing apart (at least 2 x 1 lights).
  const auto axis = [&](double length) {
    const int n = std::max(1, static_cast<int>(std::lround(length / w.spacing_m)));
    std::vector<double> v;
    const double x0 = 0.5 * (length - (n - 1) * w.spacing_m);
    for (int i = 0; i < n; ++i) v.push_back(x0 + i * w.spacing_m);
    return v;
  };
  const std::vector<double> xs = axis(s.room_x_m), ys = axis(s.room_y_m);
  std::mt19937_64 rng = make_rng(seed, RandomStream::world, 2);
  std::uniform_real_distribution<double> jitter(-0.25 * w.spacing_m, 0.25 * w.spacing_m);
  std::vector<Eigen::Vector3d> p;
  for (double y : ys)
    for (double x : xs) {
      Eigen::Vector3d q(x, y, w.ceiling_m);
      if (w.layout == "irregular") {
        q.x() = std::clamp(x + jitter(rng), 0.3, s.room_x_m - 0.3);
        q.y() = std::clamp(y + jitter(rng), 0.3, s.room_y_m - 0.3);
      }
      p.push_back(q);
    }
  if (p.size() < 2) {  // a room smaller than the spacing: a second light beside the first
    const Eigen::Vector3d first = p.front();
    p.emplace_back(std::min(s.room_x_m - 0.3, first.x() + w.spacing_m), first.y(), w.ceiling_m);
  }
  return plan_lights(s, p, w.led_diameter_m, seed);
}

WorldPlan apply_camera_mode(Scenario& s, const CameraMode& mode, std::uint64_t seed) {
  require_ceiling_camera(s);
  s.camera = camera_for_mode(mode);
  std::vector<Eigen::Vector3d> p;
  double diameter = 0.0;
  for (const Led& l : s.map.leds()) {
    p.push_back(l.p_inW);
    diameter = std::max(diameter, l.diameter_m);
  }
  return plan_lights(s, p, diameter, seed);
}

}  // namespace luxloc::sim
