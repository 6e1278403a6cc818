#pragma once
// The device height from the camera geometry (issue 16 part 3): two identified LEDs at known
// positions, seen along unit rays d_1, d_2 from the camera centre C, are C + t_i d_i. Their
// known separation and height difference fix the ranges t_i, hence C's height:
//   t_1 d_1z - t_2 d_2z = L_1z - L_2z          (vertical)
//   | t_1 d_1 - t_2 d_2 | = | L_1 - L_2 |       (the pair's length)
// Substituting t_2 leaves a quadratic in t_1 (closed form; one root for LEDs at one height).
// Neither equation involves yaw or the horizontal position (the rays' vertical components
// and their mutual angle depend on roll and pitch only), so the AHRS's yaw error and the
// filter's horizontal error do not enter: the height is measured on its own.
// Sigma: first-order propagation, by finite differences through the same solution, of the
// pixel noise (u, v of both LEDs) and of a roll / pitch error shared by both rays. With more
// than two LEDs the pair with the smallest sigma is used (pairs share LEDs: their errors are
// correlated, so they are not averaged as if independent).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/vlc/camera_geometry_fix.hpp"

namespace luxloc {

struct CameraHeightOptions {
  double pixel_sigma = 1.0;          // px per axis (the fusion passes FusionOptions::vlc_pixel_sigma)
  double attitude_sigma_rad = 0.01;  // roll / pitch error, per axis (the fusion: FusionOptions::attitude_sigma_rad)
  // A pair must subtend at least this angle (rad) at the camera: the height's error grows as
  // 1 / angle (0.15 rad: ~0.3 m of LEDs 2 m away; 1 px at f = 460 is then 1.5 % of the range).
  double min_pair_angle_rad = 0.15;
  double min_ray_elevation = 0.05;   // a ray must rise at least this much (z of the unit ray)
  // The envelope radius's error (disc_height): radius_sigma_px + radius_rel_sigma x radius.
  // On sim drone seed 1 (tuning; radii 17-35 px) the disc heights were off by -0.02 +/- 0.06 m
  // against this sigma's mean 0.095 m (98.5 % within 2 sigma, with attitude sigma 0.05 rad);
  // kept above the sim's spread for real blobs, whose edges bloom with the exposure.
  double radius_sigma_px = 0.5;
  double radius_rel_sigma = 0.02;
  // The heights of consecutive frames share most of their error (the AHRS's tilt error lasts
  // seconds, a blob's size bias as long as it stays in one part of the image): a filter that
  // took 30 of them a second as independent would claim a sigma_z several times too small.
  // The fusion weighs each at this multiple of its sigma (x2: four frames count as one).
  // Chosen on sim drone seeds 1-5 with --camera (tuning): share of poses within 1.96 sigma_z
  // 55-94 % at x1, 90-99 % at x2, 99-100 % at x4; z RMSE 0.04-0.07 m unchanged by it.
  double frame_correlation = 2.0;
};

// One LED of known diameter (issue 16 part 3, "a known LED diameter"): the blob's
// area-equivalent radius r (px, the envelope ellipse's sqrt(a b)) shrinks as 1 / range
// along its ray. The horizontal disc is projected through the camera model (distortion
// and obliquity included) at a trial range t0; the range is t0 r(t0) / r, refined once.
struct DiscSighting {
  Eigen::Vector3d p_LinW = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double radius_px = 0.0;   // measured area-equivalent radius
  double diameter_m = 0.0;  // the LED's (map), > 0
};

struct CameraHeight {
  double z_m = 0.0;      // body origin's height (world z)
  double sigma_m = 0.0;  // 1 sigma
  int led_a = -1, led_b = -1;  // indices into the sightings of the pair used
};

// Height of the body origin from >= 2 sightings under the attitude R_BtoW (its yaw does not
// matter). z_hint_m picks the root when both roots of the pair's quadratic are valid (LEDs at
// different heights); NaN: the lower camera. nullopt: fewer than two usable LEDs, a pair too
// close together in the image, or no valid root.
std::optional<CameraHeight> camera_height(const std::vector<LedSighting>& leds, const CameraModel& camera,
                                          const Eigen::Matrix3d& R_BtoW, double z_hint_m,
                                          const CameraHeightOptions& options = {});

// Height of the body origin from one LED's apparent size; nullopt when the ray does not rise
// or the size is unusable.
std::optional<CameraHeight> disc_height(const DiscSighting& led, const CameraModel& camera,
                                        const Eigen::Matrix3d& R_BtoW, const CameraHeightOptions& options = {});

// Area-equivalent radius (px) of a horizontal disc (radius_m) centred at centre_inC, under
// the world-to-camera rotation R_WtoC; NaN when part of it is behind the camera.
double projected_disc_radius_px(const CameraModel& camera, const Eigen::Matrix3d& R_WtoC,
                                const Eigen::Vector3d& centre_inC, double radius_m);

}  // namespace luxloc
