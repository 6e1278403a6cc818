#include "core/vlc/camera_model.hpp"

#include <Eigen/LU>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>

#include "core/common/input_error.hpp"
#include "core/common/yaml_reader.hpp"

namespace luxloc {
namespace {

cv::Mat read_matrix(const YamlFile& f, const char* key, int rows, int cols, bool required) {
  const cv::FileNode n = f[key];
  if (n.empty()) {
    if (required) f.fail(key, "", "missing required key");
    return {};
  }
  cv::Mat m = f.matrix(n, key);
  if (rows > 0 && cols > 0 && (m.rows * m.cols != rows * cols))
    f.fail(key, "", "expected " + std::to_string(rows) + "x" + std::to_string(cols) + ", got " + std::to_string(m.rows) +
                        "x" + std::to_string(m.cols));
  return m.reshape(1, rows > 0 ? rows : m.rows);
}

double read_positive(const YamlFile& f, const char* key, bool required, double fallback) {
  const cv::FileNode n = f[key];
  if (n.empty()) {
    if (required) f.fail(key, "", "missing required key");
    return fallback;
  }
  const double v = f.number(n, key, "");
  if (!(v > 0.0)) f.fail(key, "", "must be > 0");
  return v;
}

}  // namespace

CameraModel CameraModel::load(const std::string& path) {
  const YamlFile f(path, "camera file");
  CameraModel c;
  // Image sizes are whole pixels; 65536 is beyond any camera sensor (and keeps int math safe).
  for (const char* key : {"image_width", "image_height"}) {
    const double v = read_positive(f, key, true, 0);
    if (v != std::floor(v) || v > 65536) f.fail(key, "", "must be a whole number of pixels, 1..65536");
  }
  c.width = static_cast<int>(read_positive(f, "image_width", true, 0));
  c.height = static_cast<int>(read_positive(f, "image_height", true, 0));
  const cv::Mat K = read_matrix(f, "camera_matrix", 3, 3, true);
  c.fx = K.at<double>(0, 0);
  c.fy = K.at<double>(1, 1);
  c.cx = K.at<double>(0, 2);
  c.cy = K.at<double>(1, 2);
  if (!(c.fx > 0 && c.fy > 0)) throw InputError(path, 0, "camera_matrix", "focal lengths must be > 0");
  const cv::Mat D = read_matrix(f, "distortion_coefficients", 0, 0, false);
  if (!D.empty()) {
    const int n = D.rows * D.cols;
    if (n < 4) throw InputError(path, 0, "distortion_coefficients", "needs at least 4 values");
    if (n > 5)
      for (int i = 5; i < n; ++i)
        if (D.at<double>(i) != 0.0)
          throw InputError(path, 0, "distortion_coefficients",
                           "rational / thin-prism terms (k4..) are not supported; recalibrate with 5");
    for (int i = 0; i < std::min(n, 5); ++i) c.dist[static_cast<std::size_t>(i)] = D.at<double>(i);
  }
  c.row_time_known = !f["row_time_us"].empty();
  c.exposure_known = !f["exposure_us"].empty();
  const double row_time_us = read_positive(f, "row_time_us", false, 30.0);
  const double exposure_us = read_positive(f, "exposure_us", false, 100.0);
  // Physically impossible timings are refused here, at the edge.
  if (!plausible_row_time_us(row_time_us))
    f.fail("row_time_us", "", "must be 1-200 (microseconds per row; webcams read a row in 15-45 us)");
  if (!plausible_exposure_us(exposure_us)) f.fail("exposure_us", "", "must be 1-1000000 (microseconds)");
  c.row_time_s = row_time_us * 1e-6;
  c.exposure_s = exposure_us * 1e-6;
  const cv::Mat R = read_matrix(f, "R_body_camera", 3, 3, false);
  if (!R.empty()) {
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) c.R_CtoB(r, k) = R.at<double>(r, k);
    const double ortho = (c.R_CtoB.transpose() * c.R_CtoB - Eigen::Matrix3d::Identity()).norm();
    if (ortho > 1e-3 || c.R_CtoB.determinant() < 0.0)
      throw InputError(path, 0, "R_body_camera", "not a rotation matrix (orthonormal, det +1)");
  }
  const cv::Mat t = read_matrix(f, "t_body_camera", 3, 1, false);
  if (!t.empty())
    for (int r = 0; r < 3; ++r) c.p_CinB(r) = t.at<double>(r);
  return c;
}

void CameraModel::save(const std::string& path) const {
  cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  if (!fs.isOpened()) throw InputError(path, 0, "", "cannot write camera file");
  fs << "image_width" << width << "image_height" << height;
  fs << "camera_matrix" << cv::Mat(cv::Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1));
  fs << "distortion_coefficients" << cv::Mat(1, 5, CV_64F, const_cast<double*>(dist.data())).clone();
  // A guessed timing is left out, so the file says what is known (load() guesses again).
  if (row_time_known) fs << "row_time_us" << row_time_s * 1e6;
  if (exposure_known) fs << "exposure_us" << exposure_s * 1e6;
  cv::Mat R(3, 3, CV_64F), t(3, 1, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) R.at<double>(r, k) = R_CtoB(r, k);
    t.at<double>(r) = p_CinB(r);
  }
  fs << "R_body_camera" << R << "t_body_camera" << t;
}

bool CameraModel::has_distortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

bool CameraModel::project(const Eigen::Vector3d& p_inC, Eigen::Vector2d& uv) const {
  if (p_inC.z() <= 1e-9) return false;
  double x = p_inC.x() / p_inC.z(), y = p_inC.y() / p_inC.z();
  if (has_distortion()) {
    const double r2 = x * x + y * y;
    const double radial = 1 + dist[0] * r2 + dist[1] * r2 * r2 + dist[4] * r2 * r2 * r2;
    const double xd = x * radial + 2 * dist[2] * x * y + dist[3] * (r2 + 2 * x * x);
    const double yd = y * radial + dist[2] * (r2 + 2 * y * y) + 2 * dist[3] * x * y;
    x = xd;
    y = yd;
  }
  uv = {fx * x + cx, fy * y + cy};
  return true;
}

Eigen::Vector3d CameraModel::bearing(const Eigen::Vector2d& uv) const {
  const double xd = (uv.x() - cx) / fx, yd = (uv.y() - cy) / fy;
  double x = xd, y = yd;
  if (has_distortion()) {
    // Fixed-point inversion of the distortion model, as cv::undistortPoints does.
    for (int it = 0; it < 20; ++it) {
      const double r2 = x * x + y * y;
      const double radial = 1 + dist[0] * r2 + dist[1] * r2 * r2 + dist[4] * r2 * r2 * r2;
      const double dx = 2 * dist[2] * x * y + dist[3] * (r2 + 2 * x * x);
      const double dy = dist[2] * (r2 + 2 * y * y) + 2 * dist[3] * x * y;
      x = (xd - dx) / radial;
      y = (yd - dy) / radial;
    }
  }
  return Eigen::Vector3d(x, y, 1.0).normalized();
}

}  // namespace luxloc
