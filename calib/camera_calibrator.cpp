#include "calib/camera_calibrator.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace luxloc::calib {

std::size_t CameraCalibResult::used() const {
  return static_cast<std::size_t>(std::count_if(views.begin(), views.end(), [](const CalibView& v) { return v.used; }));
}

std::vector<cv::Point3f> chessboard_points(const CameraCalibOptions& o) {
  std::vector<cv::Point3f> p;
  for (int r = 0; r < o.board.height; ++r)
    for (int c = 0; c < o.board.width; ++c)
      p.emplace_back(static_cast<float>(c * o.square_m), static_cast<float>(r * o.square_m), 0.0f);
  return p;
}

std::vector<cv::Point2f> detect_chessboard(const cv::Mat& gray, const CameraCalibOptions& o) {
  std::vector<cv::Point2f> corners;
  if (gray.empty()) return corners;
  const bool found = cv::findChessboardCorners(
      gray, o.board, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_FAST_CHECK | cv::CALIB_CB_NORMALIZE_IMAGE);
  if (!found) return {};
  cv::cornerSubPix(gray, corners, cv::Size(o.subpix_window, o.subpix_window), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
  return corners;
}

CameraCalibResult calibrate_camera(const std::vector<cv::Mat>& images, const std::vector<std::string>& names,
                                   const CameraCalibOptions& o) {
  CameraCalibResult res;
  cv::Size size;
  for (std::size_t i = 0; i < images.size(); ++i) {
    CalibView v;
    v.name = i < names.size() ? names[i] : "image " + std::to_string(i + 1);
    if (!images[i].empty()) {
      if (size.area() == 0) size = images[i].size();
      if (images[i].size() != size)
        throw std::invalid_argument(v.name + ": image size " + std::to_string(images[i].cols) + "x" +
                                    std::to_string(images[i].rows) + " differs from the first image's " +
                                    std::to_string(size.width) + "x" + std::to_string(size.height));
      v.corners = detect_chessboard(images[i], o);
      v.found = v.used = !v.corners.empty();
    }
    res.views.push_back(std::move(v));
  }
  const auto found = static_cast<int>(
      std::count_if(res.views.begin(), res.views.end(), [](const CalibView& v) { return v.found; }));
  if (found < o.min_views)
    throw std::invalid_argument("chessboard " + std::to_string(o.board.width) + "x" + std::to_string(o.board.height) +
                                " found in " + std::to_string(found) + " of " + std::to_string(images.size()) +
                                " images; at least " + std::to_string(o.min_views) + " needed");

  const std::vector<cv::Point3f> board = chessboard_points(o);
  const int flags = cv::CALIB_USE_LU | (o.free_k3 ? 0 : cv::CALIB_FIX_K3);
  cv::Mat K, dist;
  while (true) {
    std::vector<std::vector<cv::Point3f>> obj;
    std::vector<std::vector<cv::Point2f>> img;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < res.views.size(); ++i)
      if (res.views[i].used) {
        obj.push_back(board);
        img.push_back(res.views[i].corners);
        index.push_back(i);
      }
    K = cv::Mat::eye(3, 3, CV_64F);
    dist = cv::Mat::zeros(5, 1, CV_64F);
    std::vector<cv::Mat> rvecs, tvecs;
    res.rms_px = cv::calibrateCamera(obj, img, size, K, dist, rvecs, tvecs, flags);
    ++res.rounds;
    std::vector<double> errs;
    for (std::size_t k = 0; k < index.size(); ++k) {
      std::vector<cv::Point2f> proj;
      cv::projectPoints(board, rvecs[k], tvecs[k], K, dist, proj);
      double s = 0.0;
      for (std::size_t j = 0; j < proj.size(); ++j) {
        const cv::Point2f d = proj[j] - img[k][j];
        s += d.dot(d);
      }
      res.views[index[k]].rms_px = std::sqrt(s / static_cast<double>(proj.size()));
      errs.push_back(res.views[index[k]].rms_px);
    }
    std::vector<double> sorted = errs;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double limit = std::max(o.reject_min_px, o.reject_factor * sorted[sorted.size() / 2]);
    // One view per round, the worst: a bad view inflates the others' errors until it is out.
    const auto worst = static_cast<std::size_t>(std::max_element(errs.begin(), errs.end()) - errs.begin());
    if (!(errs[worst] > limit) || static_cast<int>(index.size()) - 1 < o.min_views) break;
    res.views[index[worst]].used = false;
  }
  // Dropped views: their error under the final intrinsics (pose re-solved).
  for (CalibView& v : res.views)
    if (v.found && !v.used) {
      cv::Mat rvec, tvec;
      cv::solvePnP(board, v.corners, K, dist, rvec, tvec);
      std::vector<cv::Point2f> proj;
      cv::projectPoints(board, rvec, tvec, K, dist, proj);
      double s = 0.0;
      for (std::size_t j = 0; j < proj.size(); ++j) s += (proj[j] - v.corners[j]).dot(proj[j] - v.corners[j]);
      v.rms_px = std::sqrt(s / static_cast<double>(proj.size()));
    }
  CameraModel& c = res.camera;
  c.width = size.width;
  c.height = size.height;
  c.fx = K.at<double>(0, 0);
  c.fy = K.at<double>(1, 1);
  c.cx = K.at<double>(0, 2);
  c.cy = K.at<double>(1, 2);
  for (int i = 0; i < 5; ++i) c.dist[static_cast<std::size_t>(i)] = dist.at<double>(i);
  return res;
}

}  // namespace luxloc::calib
