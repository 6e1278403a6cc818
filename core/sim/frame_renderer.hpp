#pragma once
// Rolling-shutter frame synthesis: ceiling LEDs driven by square waves, imaged by a
// camera whose rows are exposed one after another (SEEDS.md A, S202). See docs/SIMULATOR.md.
#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <random>
#include <vector>

#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc::sim {

struct RenderOptions {
  double peak_dn = 235.0;       // DN above black of an LED seen head-on, on for the whole exposure
  double black_dn = 6.0;        // black level
  double read_noise_dn = 1.2;   // Gaussian read noise (DN, 1 sigma)
  bool shot_noise = true;       // Poisson-like noise proportional to sqrt(signal)
  double dn_per_electron = 0.04;  // conversion gain for shot noise: var = signal * gain (DN^2)
  double blur_px = 0.7;         // optics blur (Gaussian sigma, pixels)
  double ambient_dn = 0.0;      // uniform ambient light
  bool lights_on = true;        // false: every LED dark (blackout)
  int rim_points = 64;          // polygon vertices of a projected LED disc
  int subrows = 8;              // vertical supersampling of the disc coverage (exact horizontally)
};

// What the renderer put into a frame: ground truth for decoder tests.
struct RenderedLed {
  int id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // projected centre (distorted pixels)
  double radius_px = 0.0;                        // mean projected radius
  double row_min = 0.0, row_max = 0.0;           // rows spanned by the disc
  bool fully_inside = false;                     // whole disc within the image
  double t_center_s = 0.0;                       // exposure start of the centre row
};

struct RenderedFrame {
  cv::Mat gray;  // CV_8UC1, camera.height x camera.width
  std::vector<RenderedLed> leds;
};

// World pose of the body at time t (seconds): T_BtoW (rotation R_BtoW, translation p_BinW).
using PoseAt = std::function<Eigen::Isometry3d(double t_s)>;

// Renders the frame whose row 0 starts its exposure at t0_s. Each LED is projected with
// the pose at the time its own rows are read out (rolling shutter), and every row's
// brightness is the LED's on-time fraction within that row's exposure window.
// `phase_s[i]` is LED i's square-wave phase offset (seconds); empty = all zero.
RenderedFrame render_frame(const CameraModel& camera, const LedMap& map, const PoseAt& pose_at,
                           double t0_s, const RenderOptions& options, std::mt19937_64& rng,
                           const std::vector<double>& phase_s = {});

// Fraction of [t_start, t_start + exposure] during which a square wave of frequency f,
// duty d and phase offset phase_s is on (on when frac(f (t - phase)) < d). Exact.
double on_fraction(double f_hz, double duty, double phase_s, double t_start_s, double exposure_s);

}  // namespace luxloc::sim
