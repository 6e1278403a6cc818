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
// ("bad frame"). The device going away (unplugged: ENODEV, EIO, POLLERR):
//   on_loss=end  (default) the stream ends with failure() set: the run goes on with the
//                other sources, flushes every pose and exits 1;
//   on_loss=wait the loss is counted ("device lost") and reported on stderr, the camera is
//                re-opened (same options) every reopen_interval_s until it is back or a
//                stop is requested; frames resume on the same timeline.
// No frame for kSilentWarnS (poll timeouts) is reported once on stderr; the source waits on.
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>

#include "core/pipeline/source.hpp"
#include "plugins/serial/serial_port.hpp"
#include "plugins/serial/serial_stream.hpp"
#include "plugins/source_spec.hpp"
#include "plugins/v4l2/v4l2_camera.hpp"

namespace luxloc {

// Parses the spec; throws InputError (field = the key) for bad or unknown keys.
V4l2CameraOptions v4l2_options_from_spec(const SourceSpec& spec);

struct V4l2LossOptions {
  OnLoss on_loss = OnLoss::end;
  double reopen_interval_s = 0.5;
  int poll_timeout_ms = 200;  // a blocked next() re-checks the stop flag this often anyway
  double silent_warn_s = 2.0;  // no frame for this long: said once on stderr
  bool report_to_stderr = true;
  // on_loss (end|wait) from the spec; throws InputError (field on_loss).
  static V4l2LossOptions from_spec(const SourceSpec& spec);
};

class V4l2CameraSource final : public Source {
 public:
  // Opens the camera; throws V4l2Error (a std::runtime_error: exit 1) when it cannot.
  // `io`: the device calls (nullptr: libv4l2; tests pass a fake device).
  explicit V4l2CameraSource(V4l2CameraOptions options, V4l2LossOptions loss = {},
                            std::shared_ptr<V4l2Io> io = nullptr);

  std::string name() const override { return "v4l2:" + options_.path; }
  bool next(SensorData& out) override;
  void request_stop() override;
  bool live() const override { return true; }
  std::string failure() const override;

  const V4l2Camera& camera() const { return *camera_; }  // not while re-opening
  std::uint64_t frames() const { return frames_; }
  std::uint64_t losses() const { return losses_; }  // times the device went away
  std::uint64_t timeouts() const { return timeouts_; }  // poll timeouts without a frame

 private:
  bool reopen();  // on_loss=wait: false when stopped first

  V4l2CameraOptions options_;
  V4l2LossOptions loss_;
  std::shared_ptr<V4l2Io> io_;
  std::unique_ptr<V4l2Camera> camera_;
  UniqueFd wake_read_, wake_write_;
  std::atomic<bool> stop_{false};
  bool lost_ = false;
  bool warned_arrival_ = false;
  bool warned_end_of_frame_ = false;
  mutable std::mutex failure_mutex_;
  std::string failure_;
  TimeNs last_t_ = 0;
  TimeNs last_frame_arrival_ = 0;
  bool warned_silent_ = false;
  std::uint64_t frames_ = 0, losses_ = 0, timeouts_ = 0;
};

// The `v4l2` kind for make_live_source; prints the driver's adjustments to stderr.
SourcePtr make_v4l2_camera_source(const SourceSpec& spec);

}  // namespace luxloc
