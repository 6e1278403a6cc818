#pragma once
// A textured floor seen by a downward camera (the `floor` scenario, SEEDS.md C.5's visual
// odometry): a procedural texture (multi-scale blurred noise, deterministic for a seed)
// covering the floor; each pixel's ray (CameraModel::bearing) is cast from the camera
// pose and meets the plane z = 0 there. Global shutter, linear texture sampling, Gaussian
// read noise.
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <random>
#include <vector>

#include "core/vlc/camera_model.hpp"

namespace luxloc::sim {

class FloorRenderer {
 public:
  // Texture over [x0, x0 + width] x [y0, y0 + height] (m) at m_per_px.
  FloorRenderer(const CameraModel& camera, double x0, double y0, double width_m, double height_m, double m_per_px,
                std::uint64_t seed);
  cv::Mat render(const Eigen::Isometry3d& T_BtoW, std::mt19937_64& rng, double noise_dn = 2.0) const;
  const cv::Mat& texture() const { return texture_; }

 private:
  CameraModel camera_;
  double x0_, y0_, m_per_px_;
  cv::Mat texture_;                      // CV_8UC1, row = y, column = x
  std::vector<Eigen::Vector3d> bearings_;  // per pixel, camera frame
};

}  // namespace luxloc::sim
