#pragma once
// `v4l2:/dev/videoN[,width=..,height=..,fps=..,exposure_us=..,gain=..,format=grey|yuyv|mjpeg]`
// (SPEC.md "Source kinds"): a live rolling-shutter camera as a Source of FrameSamples.
// next() blocks until a frame arrives; request_stop() (any thread) wakes it through a
// self-pipe. Frame time: the driver's CLOCK_MONOTONIC buffer timestamp (V4l2Camera), on the
// same timeline as the serial sources' arrival stamps.
//
// Defaults: 640x480, 30 fps, exposure_us=100 (manual; exposure_us=auto leaves the camera's
// auto exposure alone), gain unchanged, format = the best native of GREY, YUYV, MJPEG.
// A frame that does not convert (corrupt JPEG, short buffer) is skipped and counted
// ("bad frame"); the device going away ends the stream with failure() set (exit 1).
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>

#include "core/pipeline/source.hpp"
#include "plugins/serial/serial_port.hpp"
#include "plugins/source_spec.hpp"
#include "plugins/v4l2/v4l2_camera.hpp"

namespace luxloc {

// Parses the spec; throws InputError (field = the key) for bad or unknown keys.
V4l2CameraOptions v4l2_options_from_spec(const SourceSpec& spec);

class V4l2CameraSource final : public Source {
 public:
  // Opens the camera; throws V4l2Error (a std::runtime_error: exit 1) when it cannot.
  explicit V4l2CameraSource(V4l2CameraOptions options);

  std::string name() const override { return "v4l2:" + camera_->options().path; }
  bool next(SensorData& out) override;
  void request_stop() override;
  bool live() const override { return true; }
  std::string failure() const override;

  const V4l2Camera& camera() const { return *camera_; }
  std::uint64_t frames() const { return frames_; }

 private:
  std::unique_ptr<V4l2Camera> camera_;
  UniqueFd wake_read_, wake_write_;
  std::atomic<bool> stop_{false};
  bool lost_ = false;
  bool warned_arrival_ = false;
  mutable std::mutex failure_mutex_;
  std::string failure_;
  TimeNs last_t_ = 0;
  std::uint64_t frames_ = 0;
};

// The `v4l2` kind for make_live_source; prints the driver's adjustments to stderr.
SourcePtr make_v4l2_camera_source(const SourceSpec& spec);

}  // namespace luxloc
