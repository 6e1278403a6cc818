#pragma once
// A V4L2 capture device through libv4l2 (v4l2_open / v4l2_ioctl / v4l2_mmap): format
// negotiation, frame rate, manual exposure and gain, memory-mapped streaming, driver
// timestamps. RAII: the destructor stops streaming, unmaps and closes. Not thread-safe,
// except that grab() can be woken from another thread through `wake_fd`.
//
// Order of the set-up (each step can fail with a V4l2Error naming what and why):
//   open -> VIDIOC_QUERYCAP (a video capture device with streaming I/O) -> VIDIOC_S_FMT
//   (the requested or the best native format: GREY > YUYV > MJPEG) -> VIDIOC_S_PARM
//   (frame interval) -> controls: auto exposure off (V4L2_EXPOSURE_MANUAL) first, then
//   exposure_dynamic_framerate / exposure_auto_priority off, then the exposure in 100 us
//   units and the gain -> VIDIOC_REQBUFS + v4l2_mmap + VIDIOC_QBUF -> VIDIOC_STREAMON.
// The exposure is set after the format and the frame interval: drivers clamp it to the
// frame interval of the mode in force.
//
// Timestamps (plugins/v4l2/buffer_time.hpp): with V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC the
// buffer's timestamp is on CLOCK_MONOTONIC, the clock of our live timeline, and is used as
// is; an old driver's CLOCK_REALTIME stamp (flag UNKNOWN) is moved onto it; otherwise the
// frame is stamped with CLOCK_MONOTONIC when it is dequeued (later than the exposure by the
// readout and transfer) and arrival_stamped() says so. A driver stamp that marks the end of
// the frame (TSTAMP_SRC_EOF) is moved back by the exposure and the readout of rows 0..H-1
// when the row time is known (options row_time_us), so every frame time is row 0's exposure
// start as SPEC.md has it; end_of_frame_shift_ns() says by how much (0: not moved).
//
// Every device call goes through V4l2Io (plugins/v4l2/v4l2_io.hpp): the real libv4l2, or a
// fake device in the tests.
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/common/time.hpp"
#include "plugins/v4l2/buffer_time.hpp"
#include "plugins/v4l2/exposure_control.hpp"
#include "plugins/v4l2/pixel_format.hpp"
#include "plugins/v4l2/v4l2_io.hpp"

namespace luxloc {

class V4l2Error : public std::runtime_error {
 public:
  enum class Kind { no_device, permission, busy, not_capture, unsupported_format, no_manual_exposure, io };
  V4l2Error(Kind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

struct V4l2CameraOptions {
  std::string path = "/dev/video0";
  int width = 640;
  int height = 480;
  double fps = 30.0;
  std::optional<PixelFormat> format;  // none: best native of GREY, YUYV, MJPEG
  // Manual exposure; none: leave the camera's exposure as it is (auto). The stripes need
  // a short one (FIELD_NOTES: <= ~300 us for 2-3 kHz LEDs), so the source's default is 100 us.
  std::optional<double> exposure_us = 100.0;
  std::optional<double> gain;  // V4L2_CID_GAIN raw value, clamped to its range; none: unchanged
  int buffers = 4;
  // The rolling shutter's row time (camera.yaml row_time, `calib rowtime`): with it a
  // driver's end-of-frame stamp is moved back to row 0's exposure start.
  std::optional<double> row_time_us;
};

// One integer / menu / boolean control as the driver reports it.
struct V4l2Control {
  std::uint32_t id = 0;
  std::string name;       // VIDIOC_QUERYCTRL's
  std::string ctl_name;   // v4l2-ctl's (v4l2_control_name)
  std::uint32_t type = 0;
  ControlRange range;
  std::int32_t value = 0;
  bool readable = false;  // value holds the current value
  bool inactive = false;  // V4L2_CTRL_FLAG_INACTIVE (e.g. exposure while auto exposure is on)
  std::vector<std::pair<std::int32_t, std::string>> menu;  // menu controls: index, name
};

class V4l2Camera {
 public:
  // Opens and configures; streaming starts at once. Throws V4l2Error. `io`: the device
  // calls (nullptr: the real device through libv4l2; tests pass a fake device).
  explicit V4l2Camera(V4l2CameraOptions options, std::shared_ptr<V4l2Io> io = nullptr);
  ~V4l2Camera();
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  enum class GrabStatus { frame, timeout, woken, bad_frame };
  // Waits up to timeout_ms for a frame (or for `wake_fd`, when >= 0, to become readable).
  // frame: `gray` and `t` set; bad_frame: the buffer did not convert (error()), the stream
  // goes on. Throws V4l2Error(io) when the device is gone (unplugged: ENODEV, EIO, POLLERR).
  GrabStatus grab(int timeout_ms, int wake_fd, cv::Mat& gray, TimeNs& t);

  const V4l2CameraOptions& options() const { return options_; }
  const std::string& driver() const { return driver_; }
  const std::string& card() const { return card_; }
  PixelFormat format() const { return format_; }
  int width() const { return layout_.width; }
  int height() const { return layout_.height; }
  double fps() const { return fps_; }                     // as set by the driver (0 = unknown)
  std::optional<double> exposure_us() const { return exposure_us_; }  // as read back
  bool arrival_stamped() const { return arrival_stamped_; }
  BufferClock clock() const { return clock_; }  // of the last frame's time stamp
  // The last frame's driver stamp marked the end of the frame; and the time it was moved back
  // by (0 when the row time is not known: then the frame is late by its readout).
  bool end_of_frame_stamped() const { return end_of_frame_; }
  TimeNs end_of_frame_shift_ns() const;
  const std::string& last_error() const { return error_; }
  // What the driver changed from the request (resolution, frame rate, exposure clamped...).
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  void open_device();
  void negotiate_format();
  void set_frame_rate();
  void set_exposure_and_gain();
  void start_streaming();
  void stop_streaming() noexcept;
  int xioctl(unsigned long request, void* arg) const;

  V4l2CameraOptions options_;
  std::shared_ptr<V4l2Io> io_;
  int fd_ = -1;
  std::string driver_, card_;
  PixelFormat format_ = PixelFormat::yuyv;
  FrameLayout layout_;
  double fps_ = 0.0;
  std::optional<double> exposure_us_;
  bool streaming_ = false;
  bool arrival_stamped_ = false;
  bool end_of_frame_ = false;
  BufferClock clock_ = BufferClock::arrival;
  struct Buffer {
    void* start = nullptr;
    std::size_t length = 0;
  };
  std::vector<Buffer> buffers_;
  std::vector<std::string> notes_;
  std::string error_;
};

// All controls of an open descriptor (VIDIOC_QUERYCTRL with V4L2_CTRL_FLAG_NEXT_CTRL).
std::vector<V4l2Control> query_controls(int fd);
std::vector<V4l2Control> query_controls(V4l2Io& io, int fd);
// "exposure_time_absolute (1..5000 x 100 us), gain (0..255)": for messages.
std::string describe_controls(const std::vector<V4l2Control>& controls);

}  // namespace luxloc
