#pragma once
// Monocular visual odometry over a plane (SEEDS.md C.5): a camera looking straight down at
// the floor from a known height h. Between consecutive frames:
// 1. features: cv::goodFeaturesToTrack (re-detected when fewer than min_features survive),
//    tracked with pyramidal Lucas-Kanade (cv::calcOpticalFlowPyrLK);
// 2. pixels -> metres on the floor: undistorted with the calibrated intrinsics
//    (cv::undistortPoints, Zhang calibration) and scaled by h (a floor point at camera
//    coordinates (X, Y, h) has normalised coordinates (X/h, Y/h));
// 3. the 4-parameter similarity [x2; y2] = k R(theta) [x1; y1] + [tx; ty] fitted robustly
//    (cv::estimateAffinePartial2D, RANSAC) — C.5's model, with k ~ 1 checking the height;
// 4. the camera's motion is the inverse of the floor's apparent motion: displacement
//    -R^T t in the previous camera frame, rotated into the body with R_CtoB; the yaw
//    change about body z is theta (camera z points down).
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/common/time.hpp"
#include "core/vlc/camera_model.hpp"

namespace luxloc {

struct FloorOdometryOptions {
  int max_features = 300;
  double quality = 0.01;
  double min_distance_px = 7.0;
  int min_features = 120;   // re-detect below this many tracked features
  int window_px = 21;
  int pyramid_levels = 3;
  double ransac_px = 1.0;   // inlier threshold, pixels
  int min_inliers = 25;
};

struct FloorMotion {
  double dt_s = 0.0;
  Eigen::Vector2d d_inB = Eigen::Vector2d::Zero();  // body displacement, previous body frame (x fwd, y left), m
  double dyaw_rad = 0.0;                            // yaw change about body z
  double scale = 1.0;                               // k of the similarity (1: height right, floor flat)
  int inliers = 0;
};

class FloorOdometry {
 public:
  // `height_m`: camera above the floor. The camera must look (about) straight down.
  FloorOdometry(const CameraModel& camera, double height_m, const FloorOdometryOptions& options = {});
  // Motion since the previous frame; nullopt for the first frame or a failed fit (the next
  // frame then starts afresh from this one).
  std::optional<FloorMotion> process(const cv::Mat& gray, TimeNs t);
  std::size_t tracked() const { return prev_pts_.size(); }

 private:
  void detect(const cv::Mat& gray);

  CameraModel camera_;
  double height_m_;
  FloorOdometryOptions options_;
  cv::Mat K_, dist_;
  cv::Mat prev_;
  std::vector<cv::Point2f> prev_pts_;
  TimeNs t_prev_ = 0;
};

}  // namespace luxloc
