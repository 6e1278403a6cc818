#pragma once
// The live view's camera picture: the fusion thread offers every decoded frame; at most
// one per `interval` is kept (a copy of the image and the identified LEDs' centres, ids
// and radii, so the source may reuse its buffers); an HTTP thread encodes the kept one as
// a JPEG with the LEDs circled, once per frame whatever the number of browsers.
#include <chrono>
#include <cstdint>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/common/samples.hpp"
#include "core/vlc/led_observation.hpp"

namespace luxloc {

class CameraSnapshot {
 public:
  explicit CameraSnapshot(std::chrono::milliseconds interval) : interval_(interval) {}

  // The fusion thread: true when this frame was kept (its number is then number()).
  bool offer(const FrameSample& frame, const std::vector<LedObservation>& leds);
  std::uint64_t number() const;  // 0: none yet
  // The kept frame as JPEG with the LEDs circled and labelled; empty when none.
  std::string jpeg();

 private:
  struct Blob {
    cv::Point2d uv;
    double radius_px;
    int id;
  };
  const std::chrono::milliseconds interval_;
  mutable std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
  cv::Mat gray_;
  std::vector<Blob> blobs_;
  std::uint64_t number_ = 0;
  std::uint64_t encoded_number_ = 0;
  std::string encoded_;
};

}  // namespace luxloc
