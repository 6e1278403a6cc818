#include "core/vlc/frame_levels.hpp"

#include <algorithm>
#include <array>
#include <opencv2/imgproc.hpp>

namespace luxloc {

const cv::Mat* as_gray8(const cv::Mat& in, cv::Mat& buffer) {
  switch (in.type()) {
    case CV_8UC1:
      return &in;
    case CV_8UC3:
      cv::cvtColor(in, buffer, cv::COLOR_BGR2GRAY);
      return &buffer;
    case CV_8UC4:
      cv::cvtColor(in, buffer, cv::COLOR_BGRA2GRAY);
      return &buffer;
    case CV_16UC1:
      in.convertTo(buffer, CV_8U, 1.0 / 256.0);
      return &buffer;
    default:
      return nullptr;
  }
}

FrameLevels frame_levels(const cv::Mat& g, double min_contrast_dn, double threshold_sigma, double background_quantile) {
  std::array<int, 256> hist{};
  const int sr = std::max(1, g.rows / 120), sc = std::max(1, g.cols / 160);
  int n = 0;
  for (int r = sr / 2; r < g.rows; r += sr) {
    const uchar* p = g.ptr<uchar>(r);
    for (int c = sc / 2; c < g.cols; c += sc, ++n) ++hist[p[c]];
  }
  auto quantile = [&](double q) {
    const double target = q * n;
    int acc = 0;
    for (int i = 0; i < 256; ++i) {
      acc += hist[static_cast<std::size_t>(i)];
      if (acc >= target) return i;
    }
    return 255;
  };
  FrameLevels lv;
  const double q = std::clamp(background_quantile, 0.0, 0.6);
  lv.background = quantile(q);
  lv.noise = std::max(0.5, static_cast<double>(quantile(q + 0.3413) - quantile(q)));
  lv.threshold = lv.background + std::max(min_contrast_dn, threshold_sigma * lv.noise);
  return lv;
}

}  // namespace luxloc
