#pragma once
// A position fix from one camera frame (SEEDS.md A, S2: "VLC fix"), and the per-LED
// measurement function that predicts where an LED appears for a given body pose (what a
// particle filter weighs particles with: tight coupling).
#include <Eigen/Core>
#include <optional>

#include "core/vlc/camera_model.hpp"

namespace luxloc {

struct VlcFix {
  enum class Method { Bearing, Pnp, Rss };
  Eigen::Vector3d p_BinW = Eigen::Vector3d::Zero();      // body position, world (ENU), m
  Eigen::Matrix3d R_BtoW = Eigen::Matrix3d::Identity();  // attitude used (Bearing, Rss) or estimated (Pnp)
  Eigen::Matrix2d cov_xy = Eigen::Matrix2d::Identity();  // 1-sigma^2 of x, y (m^2)
  double sigma_z = 0.0;     // 1-sigma of z when it was estimated, else 0
  int n_leds = 0;           // LEDs used
  double residual_px = 0.0;  // RMS reprojection error of the LEDs at the fix (Rss: RMS log-power residual)
  Method method = Method::Bearing;
  bool valid = false;       // false: no fix (too few LEDs, degenerate geometry, bad input); nothing is NaN
};

// Camera-frame position of a world point seen from body pose (R_BtoW, p_BinW):
// p_LinC = R_CtoB^T (R_BtoW^T (p_LinW - p_BinW) - p_CinB).
inline Eigen::Vector3d world_to_camera(const CameraModel& camera, const Eigen::Matrix3d& R_BtoW,
                                       const Eigen::Vector3d& p_BinW, const Eigen::Vector3d& p_LinW) {
  return camera.R_CtoB.transpose() * (R_BtoW.transpose() * (p_LinW - p_BinW) - camera.p_CinB);
}

// The measurement function: distorted pixel of the LED at p_LinW for the body at
// (R_BtoW, p_BinW); nullopt when the LED is behind the camera.
inline std::optional<Eigen::Vector2d> predict_pixel(const CameraModel& camera, const Eigen::Matrix3d& R_BtoW,
                                                    const Eigen::Vector3d& p_BinW, const Eigen::Vector3d& p_LinW) {
  Eigen::Vector2d uv;
  if (!camera.project(world_to_camera(camera, R_BtoW, p_BinW, p_LinW), uv)) return std::nullopt;
  return uv;
}

}  // namespace luxloc
