#include "plugins/web/camera_snapshot.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace luxloc {

bool CameraSnapshot::offer(const FrameSample& frame, const std::vector<LedObservation>& leds) {
  const auto now = std::chrono::steady_clock::now();
  if (frame.gray.empty()) return false;
  {
    std::lock_guard lock(mutex_);
    if (number_ > 0 && now - last_ < interval_) return false;
  }
  // Copied outside the lock; a few frames a second, one memcpy each.
  cv::Mat copy = frame.gray.clone();
  std::vector<Blob> blobs;
  for (const LedObservation& o : leds) blobs.push_back({{o.uv.x(), o.uv.y()}, o.radius_px, o.led_id});
  std::lock_guard lock(mutex_);
  last_ = now;
  gray_ = std::move(copy);
  blobs_ = std::move(blobs);
  ++number_;
  return true;
}

std::uint64_t CameraSnapshot::number() const {
  std::lock_guard lock(mutex_);
  return number_;
}

std::string CameraSnapshot::jpeg() {
  cv::Mat gray;
  std::vector<Blob> blobs;
  std::uint64_t n = 0;
  {
    std::lock_guard lock(mutex_);
    if (number_ == 0) return {};
    if (encoded_number_ == number_) return encoded_;
    gray = gray_;  // shared, never written after offer()
    blobs = blobs_;
    n = number_;
  }
  cv::Mat bgr;
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  const int thick = std::max(1, gray.cols / 400);
  for (const Blob& b : blobs) {
    const cv::Point c(cvRound(b.uv.x), cvRound(b.uv.y));
    cv::circle(bgr, c, std::max(6, cvRound(b.radius_px * 1.3)), cv::Scalar(0, 80, 255), thick, cv::LINE_AA);
    cv::putText(bgr, std::to_string(b.id), c + cv::Point(cvRound(b.radius_px) + 6, 0), cv::FONT_HERSHEY_SIMPLEX,
                0.4 * thick + 0.3, cv::Scalar(0, 200, 255), thick, cv::LINE_AA);
  }
  std::vector<unsigned char> buf;
  cv::imencode(".jpg", bgr, buf, {cv::IMWRITE_JPEG_QUALITY, 75});
  std::string out(buf.begin(), buf.end());
  std::lock_guard lock(mutex_);
  if (n >= encoded_number_) {
    encoded_number_ = n;
    encoded_ = out;
  }
  return out;
}

}  // namespace luxloc
