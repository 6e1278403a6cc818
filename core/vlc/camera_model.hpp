#pragma once
// Calibrated rolling-shutter camera (SPEC.md "Camera file"): OpenCV pinhole intrinsics
// with the (k1, k2, p1, p2, k3) distortion model, row readout time, exposure, and the
// mounting on the body (R_CtoB = SPEC's R_body_camera: columns are camera axes in body).
#include <Eigen/Core>
#include <array>
#include <string>

namespace luxloc {

struct CameraModel {
  int width = 640;
  int height = 480;
  double fx = 500, fy = 500, cx = 320, cy = 240;
  std::array<double, 5> dist{0, 0, 0, 0, 0};  // k1 k2 p1 p2 k3
  double row_time_s = 30e-6;                  // rolling-shutter line readout time
  double exposure_s = 100e-6;
  // Whether row_time_s / exposure_s were measured or entered (set in code, or the file's key)
  // rather than the 30 us / 100 us guesses load() falls back to. A guess is never saved, and
  // what shifts timestamps by it (V4L2 end-of-frame stamps) or plans from it (calib ledmap
  // plan) asks for a known value.
  bool row_time_known = true;
  bool exposure_known = true;
  Eigen::Matrix3d R_CtoB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_CinB = Eigen::Vector3d::Zero();

  // What a camera can have, wherever a row time or exposure enters (camera.yaml, a v4l2
  // source's row_time_us=, calib camera): a row time beyond 200 us would read a 480-row
  // frame in > 96 ms (no video mode; webcams read a row in 15-45 us), below 1 us is a unit
  // slip (ns, ms); an exposure of 1 us to 1 s.
  static constexpr double kMinRowTimeUs = 1.0, kMaxRowTimeUs = 200.0;
  static constexpr double kMinExposureUs = 1.0, kMaxExposureUs = 1e6;
  static bool plausible_row_time_us(double us) { return us >= kMinRowTimeUs && us <= kMaxRowTimeUs; }
  static bool plausible_exposure_us(double us) { return us >= kMinExposureUs && us <= kMaxExposureUs; }

  // Reads camera.yaml; throws InputError naming the file and key (timings as above).
  static CameraModel load(const std::string& path);
  void save(const std::string& path) const;

  // Camera-frame point -> distorted pixel. False when the point is behind the camera.
  bool project(const Eigen::Vector3d& p_inC, Eigen::Vector2d& uv) const;
  // Distorted pixel -> unit bearing in the camera frame (iterative undistortion).
  Eigen::Vector3d bearing(const Eigen::Vector2d& uv) const;
  bool has_distortion() const;
  // Time of the exposure start of image row v after the frame time (row 0).
  double row_offset_s(double v) const { return v * row_time_s; }
};

}  // namespace luxloc
