#include "core/sim/floor_renderer.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/sim/seeding.hpp"

namespace luxloc::sim {

FloorRenderer::FloorRenderer(const CameraModel& camera, double x0, double y0, double width_m, double height_m,
                             double m_per_px, std::uint64_t seed)
    : camera_(camera), x0_(x0), y0_(y0), m_per_px_(m_per_px) {
  const int w = static_cast<int>(std::ceil(width_m / m_per_px)), h = static_cast<int>(std::ceil(height_m / m_per_px));
  std::mt19937_64 rng = make_rng(seed, RandomStream::floor_texture);
  std::normal_distribution<float> n(0.0f, 1.0f);
  // Fine grain (features a few pixels wide) plus coarse patches (a real floor's stains and
  // tiles), both band-limited so the image does not alias.
  cv::Mat fine(h, w, CV_32FC1), coarse(h / 16 + 1, w / 16 + 1, CV_32FC1);
  for (int r = 0; r < fine.rows; ++r)
    for (int c = 0; c < fine.cols; ++c) fine.at<float>(r, c) = n(rng);
  for (int r = 0; r < coarse.rows; ++r)
    for (int c = 0; c < coarse.cols; ++c) coarse.at<float>(r, c) = n(rng);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 2.0);
  cv::GaussianBlur(coarse, coarse, cv::Size(0, 0), 1.0);
  cv::resize(coarse, coarse, fine.size(), 0, 0, cv::INTER_CUBIC);
  cv::Scalar m, s;
  cv::meanStdDev(fine, m, s);
  fine = (fine - m[0]) / s[0];
  cv::meanStdDev(coarse, m, s);
  coarse = (coarse - m[0]) / s[0];
  cv::Mat f = 128.0 + 35.0 * fine + 20.0 * coarse;
  f.convertTo(texture_, CV_8UC1);
  bearings_.reserve(static_cast<std::size_t>(camera.width * camera.height));
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) bearings_.push_back(camera.bearing(Eigen::Vector2d(u, v)));
}

cv::Mat FloorRenderer::render(const Eigen::Isometry3d& T_BtoW, std::mt19937_64& rng, double noise_dn) const {
  const Eigen::Matrix3d R_CtoW = T_BtoW.linear() * camera_.R_CtoB;
  const Eigen::Vector3d p_CinW = T_BtoW * camera_.p_CinB;
  cv::Mat mapx(camera_.height, camera_.width, CV_32FC1), mapy(camera_.height, camera_.width, CV_32FC1);
  for (int v = 0; v < camera_.height; ++v)
    for (int u = 0; u < camera_.width; ++u) {
      const Eigen::Vector3d d = R_CtoW * bearings_[static_cast<std::size_t>(v * camera_.width + u)];
      float tx = -1e6f, ty = -1e6f;  // outside: the border colour
      if (d.z() < -1e-6) {
        const double s = -p_CinW.z() / d.z();
        tx = static_cast<float>((p_CinW.x() + s * d.x() - x0_) / m_per_px_ - 0.5);
        ty = static_cast<float>((p_CinW.y() + s * d.y() - y0_) / m_per_px_ - 0.5);
      }
      mapx.at<float>(v, u) = tx;
      mapy.at<float>(v, u) = ty;
    }
  cv::Mat img;
  cv::remap(texture_, img, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  if (noise_dn > 0.0) {
    cv::Mat f;
    img.convertTo(f, CV_32FC1);
    std::normal_distribution<float> n(0.0f, static_cast<float>(noise_dn));
    for (int r = 0; r < f.rows; ++r)
      for (int c = 0; c < f.cols; ++c) f.at<float>(r, c) += n(rng);
    f.convertTo(img, CV_8UC1);
  }
  return img;
}

}  // namespace luxloc::sim
