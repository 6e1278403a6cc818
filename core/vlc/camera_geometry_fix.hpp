#pragma once
// Body position from the bearings of identified LEDs (SEEDS.md A, S2: the VLC fix, here
// by angle of arrival, the camera's strength, rather than by received power).
//
// Bearing fix: each LED's pixel gives a ray in the world, d_i = R_BtoW R_CtoB bearing(uv_i),
// from the camera centre through the LED. With the device height known, one LED suffices
// (the ray meets the LED's height above the camera); with more, the camera centre is the
// least-squares point closest to all rays (angle-weighted), and with >= 2 LEDs and no
// height the height is solved too. The camera lever arm p_CinB is applied.
//
// PnP fix: with >= 3 LEDs (4 better) the full pose, attitude included, from
// cv::solvePnP (IPPE for >= 4 coplanar LEDs, SQPNP otherwise), for when the IMU attitude
// is not trusted.
//
// Covariance (both): first-order propagation of the pixel noise (sigma_px on u and v of
// every LED, independent) and, for the bearing fix, of the attitude error (sigma_att on
// each axis, one error shared by all LEDs: more LEDs do not average it out) and of the
// device height (sigma_h), by finite differences through the solver itself.
#include <cmath>
#include <limits>
#include <vector>

#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"
#include "core/vlc/led_observation.hpp"
#include "core/vlc/vlc_fix.hpp"

namespace luxloc {

// One identified LED for the solvers: world position and observed centre (distorted px).
struct LedSighting {
  Eigen::Vector3d p_LinW = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
};

struct CameraFixOptions {
  double pixel_sigma = 1.0;           // px, blob-centre noise (1 sigma, per axis)
  double attitude_sigma_rad = 0.01;   // attitude error (1 sigma, per axis)
  double height_sigma_m = 0.05;       // error of the given device height (1 sigma)
  double min_ray_elevation = 0.05;    // a ray must rise at least this much (z of the unit ray) towards its LED
  bool solve_height = false;          // with >= 2 LEDs, solve z even when the height is given
  double min_height_baseline = 0.3;   // ... only if the LEDs subtend at least this angle (rad) seen from the camera
  bool use_border_blobs = false;      // blobs cut by the border have biased centres: skipped by default
  double max_residual_px = 25.0;      // a fix whose RMS reprojection error exceeds this is not valid
};

// Accepted observations -> sightings (skips rejected ones, and border blobs unless asked).
std::vector<LedSighting> sightings_from(const std::vector<LedObservation>& observations, const LedMap& map,
                                        bool use_border_blobs = false);

// Bearing fix. device_height_m: z of the body origin, NaN when unknown (then >= 2 LEDs).
VlcFix bearing_fix(const std::vector<LedSighting>& leds, const CameraModel& camera, const Eigen::Matrix3d& R_BtoW,
                   double device_height_m = std::numeric_limits<double>::quiet_NaN(),
                   const CameraFixOptions& options = {});
VlcFix bearing_fix(const std::vector<LedObservation>& observations, const LedMap& map, const CameraModel& camera,
                   const Eigen::Matrix3d& R_BtoW, double device_height_m = std::numeric_limits<double>::quiet_NaN(),
                   const CameraFixOptions& options = {});

// PnP fix: position and attitude (R_BtoW in the result), >= 3 LEDs.
VlcFix pnp_fix(const std::vector<LedSighting>& leds, const CameraModel& camera, const CameraFixOptions& options = {});
VlcFix pnp_fix(const std::vector<LedObservation>& observations, const LedMap& map, const CameraModel& camera,
               const CameraFixOptions& options = {});

}  // namespace luxloc
