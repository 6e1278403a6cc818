#include "core/vo/floor_odometry.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace luxloc {

FloorOdometry::FloorOdometry(const CameraModel& camera, double height_m, const FloorOdometryOptions& options)
    : camera_(camera), height_m_(height_m), options_(options) {
  K_ = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  dist_ = cv::Mat(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) dist_.at<double>(i) = camera.dist[static_cast<std::size_t>(i)];
}

void FloorOdometry::detect(const cv::Mat& gray) {
  std::vector<cv::Point2f> fresh;
  cv::goodFeaturesToTrack(gray, fresh, options_.max_features, options_.quality, options_.min_distance_px);
  // Keep the tracked points, add new ones away from them.
  const double d2 = options_.min_distance_px * options_.min_distance_px;
  for (const cv::Point2f& p : fresh) {
    bool near = false;
    for (const cv::Point2f& q : prev_pts_)
      if ((p - q).dot(p - q) < d2) {
        near = true;
        break;
      }
    if (!near) prev_pts_.push_back(p);
  }
}

std::optional<FloorMotion> FloorOdometry::process(const cv::Mat& gray, TimeNs t) {
  if (gray.empty()) return std::nullopt;
  std::optional<FloorMotion> result;
  std::vector<cv::Point2f> cur_kept;
  if (!prev_.empty() && !prev_pts_.empty() && gray.size() == prev_.size()) {
    std::vector<cv::Point2f> cur;
    std::vector<unsigned char> status;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(prev_, gray, prev_pts_, cur, status, err,
                             cv::Size(options_.window_px, options_.window_px), options_.pyramid_levels);
    std::vector<cv::Point2f> a, b;
    for (std::size_t i = 0; i < cur.size(); ++i)
      if (status[i]) {
        a.push_back(prev_pts_[i]);
        b.push_back(cur[i]);
      }
    if (static_cast<int>(a.size()) >= options_.min_inliers) {
      // Pixels -> floor metres in the camera frame.
      std::vector<cv::Point2f> na, nb;
      cv::undistortPoints(a, na, K_, dist_);
      cv::undistortPoints(b, nb, K_, dist_);
      for (auto& p : na) p *= static_cast<float>(height_m_);
      for (auto& p : nb) p *= static_cast<float>(height_m_);
      std::vector<unsigned char> inl;
      const double thr = options_.ransac_px * height_m_ / (0.5 * (camera_.fx + camera_.fy));
      const cv::Mat M = cv::estimateAffinePartial2D(na, nb, inl, cv::RANSAC, thr, 2000, 0.99, 10);
      int n_in = 0;
      for (std::size_t i = 0; i < inl.size(); ++i)
        if (inl[i]) {
          ++n_in;
          cur_kept.push_back(b[i]);
        }
      if (!M.empty() && n_in >= options_.min_inliers) {
        const double c = M.at<double>(0, 0), s = M.at<double>(1, 0);
        const double k = std::hypot(c, s), theta = std::atan2(s, c);
        const Eigen::Vector2d tr(M.at<double>(0, 2), M.at<double>(1, 2));
        Eigen::Matrix2d R;
        R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
        const Eigen::Vector2d c_inC1 = -R.transpose() * tr;  // camera 2's origin in camera 1
        FloorMotion m;
        m.dt_s = ns_to_seconds(t - t_prev_);
        m.d_inB = (camera_.R_CtoB * Eigen::Vector3d(c_inC1.x(), c_inC1.y(), 0.0)).head<2>();
        m.dyaw_rad = -camera_.R_CtoB(2, 2) * theta;  // camera z down: +theta about it is +yaw
        m.scale = k;
        m.inliers = n_in;
        if (m.d_inB.allFinite() && std::isfinite(m.dyaw_rad)) result = m;
      } else {
        cur_kept.clear();
      }
    }
  }
  prev_ = gray.clone();
  prev_pts_ = cur_kept;
  t_prev_ = t;
  if (static_cast<int>(prev_pts_.size()) < options_.min_features) detect(prev_);
  return result;
}

}  // namespace luxloc
