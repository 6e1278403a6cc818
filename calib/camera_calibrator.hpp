#pragma once
// `luxloc calib camera`: Zhang's calibration (SEEDS.md C.5's "camera calibrated by Zhang's
// method") from chessboard views, with OpenCV doing the work:
// 1. detection: cv::findChessboardCorners (adaptive threshold, normalised image, fast
//    check — the flags of OpenCV's calibration sample), refined with cv::cornerSubPix
//    (11 x 11 window, 30 iterations / 1e-4 px, as the sample);
// 2. cv::calibrateCamera (k1, k2, p1, p2; k3 fixed at 0 unless free_k3, as the sample);
// 3. per-view RMS reprojection error; views whose error exceeds reject_factor x the median
//    (and reject_min_px) are dropped and the calibration repeated, until none is dropped or
//    min_views would be undercut.
// The result is SPEC.md's camera.yaml (CameraModel::save) with the rolling-shutter row
// time entered by the user.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/vlc/camera_model.hpp"

namespace luxloc::calib {

struct CameraCalibOptions {
  cv::Size board{9, 6};     // inner corners (columns x rows)
  double square_m = 0.025;  // side of a square
  bool free_k3 = false;
  double reject_factor = 3.0;
  double reject_min_px = 0.5;  // never drop a view whose error is below this
  int min_views = 5;
  int subpix_window = 11;  // half-size, as the sample's -ws
};

struct CalibView {
  std::string name;
  bool found = false;       // chessboard detected
  bool used = false;        // in the final calibration
  double rms_px = -1.0;     // reprojection error with the final intrinsics (-1: not found)
  std::vector<cv::Point2f> corners;
};

struct CameraCalibResult {
  CameraModel camera;   // intrinsics and distortion; row time etc. are the caller's
  double rms_px = 0.0;  // over the used views (cv::calibrateCamera's value)
  int rounds = 0;       // calibrations run (1 + rejection rounds)
  std::vector<CalibView> views;
  std::size_t used() const;
};

// Detects the board; empty when not found. `gray` CV_8UC1.
std::vector<cv::Point2f> detect_chessboard(const cv::Mat& gray, const CameraCalibOptions& options);
// The board's 3-D corner positions (z = 0), row by row.
std::vector<cv::Point3f> chessboard_points(const CameraCalibOptions& options);

// Calibrates from gray images of one size (names for the report). Throws
// std::invalid_argument when fewer than min_views boards are found or sizes differ.
CameraCalibResult calibrate_camera(const std::vector<cv::Mat>& images, const std::vector<std::string>& names,
                                   const CameraCalibOptions& options);

}  // namespace luxloc::calib
