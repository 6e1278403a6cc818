#pragma once
// An ioctl-level fake V4L2 capture device behind the V4l2Io seam (plugins/v4l2/v4l2_io.hpp),
// so the real V4l2Camera / V4l2CameraSource code runs without a camera (no camera,
// v4l2loopback or vivid can be had on the test machines). It implements what a UVC-style
// driver does for the calls our code makes: QUERYCAP, ENUM_FMT, S_FMT (the "driver" may
// pick another size or format), G/S_PARM, QUERYCTRL / G_CTRL / S_CTRL / QUERYMENU (controls
// that clamp, ignore a value or carry the old kernel names), REQBUFS / QUERYBUF / mmap /
// QBUF / DQBUF with a queue of driver-owned buffers, STREAMON / STREAMOFF, and poll on a
// real eventfd (so a wake-up pipe beside it works as with a real device).
//
// The test thread plays the sensor: push_frame() fills the oldest queued buffer (false
// when the application has queued none: an overrun) and wakes poll. unplug() makes every
// call on the open descriptor fail with ENODEV and poll report POLLERR; replug() lets the
// next open() find a new device. Thread-safe.
#include <linux/videodev2.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/common/time.hpp"
#include "plugins/v4l2/v4l2_io.hpp"

namespace luxloc::test {

struct FakeControl {
  enum class Behaviour { accept, clamp, ignore };
  std::uint32_t id = 0;
  std::string name;  // VIDIOC_QUERYCTRL's name
  std::uint32_t type = V4L2_CTRL_TYPE_INTEGER;
  std::int32_t minimum = 0, maximum = 0, step = 1, default_value = 0;
  std::int32_t value = 0;
  std::map<std::int32_t, std::string> menu;  // menu controls: index -> name
  Behaviour behaviour = Behaviour::accept;
  std::int32_t clamp_max = 0;  // Behaviour::clamp: the driver's real limit (below `maximum`)
};

struct FakeFrame {
  std::vector<std::uint8_t> bytes;       // copied into the buffer
  std::optional<std::uint32_t> bytesused;  // default: bytes.size()
  std::uint32_t clock_flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
  TimeNs stamp_ns = 0;  // v4l2_buffer.timestamp (0: none)
  bool error = false;   // V4L2_BUF_FLAG_ERROR
};

class FakeV4l2Device final : public V4l2Io {
 public:
  // --- the device's configuration (set before the camera opens it) ---
  int open_errno = 0;       // open() fails with this (EBUSY, EACCES...)
  int s_fmt_errno = 0;      // VIDIOC_S_FMT fails with this (EBUSY: another program streams)
  std::uint32_t caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
  std::vector<std::uint32_t> formats = {V4L2_PIX_FMT_YUYV};
  // The driver's say on the format: called with the request, may change any field.
  std::function<void(v4l2_pix_format&)> adjust_format;
  double actual_fps = 0.0;  // S_PARM: the rate the driver sets (0: the one asked for)
  std::vector<FakeControl> controls;

  // --- the sensor and the cable (test thread) ---
  bool push_frame(const FakeFrame& f);
  void unplug();
  void replug();

  // --- observations ---
  struct Counts {
    int opens = 0, closes = 0, streamons = 0, streamoffs = 0, mapped = 0, overruns = 0;
  };
  Counts counts() const;
  std::vector<std::uint32_t> dequeued() const;  // buffer indices in DQBUF order
  std::vector<std::pair<std::uint32_t, std::int32_t>> controls_set() const;  // S_CTRL id, value
  std::optional<FakeControl> control(std::uint32_t id) const;
  v4l2_pix_format format() const;

  // --- V4l2Io ---
  int open(const std::string& path, int flags) override;
  int fd_open(int fd) override { return fd; }
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(std::size_t length, int fd, std::int64_t offset) override;
  int munmap(void* start, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;

 private:
  enum class BufState { idle, queued, done, dequeued };
  struct Buffer {
    std::vector<std::uint8_t> memory;
    BufState state = BufState::idle;
    v4l2_buffer info{};
  };
  int fail(int err) const;
  bool lost(int fd) const;  // the descriptor belongs to an unplugged device
  void set_ready(bool ready);
  int control_ioctl(unsigned long request, void* arg);
  int buffer_ioctl(unsigned long request, void* arg);

  mutable std::mutex mutex_;
  std::map<int, int> fds_;  // open descriptor (an eventfd) -> device generation
  int generation_ = 0;
  bool unplugged_ = false;
  v4l2_pix_format fmt_{};
  v4l2_fract timeperframe_{1, 30};
  std::vector<Buffer> buffers_;
  std::deque<std::uint32_t> queued_, done_;
  bool streaming_ = false;
  std::uint32_t sequence_ = 0;
  Counts counts_;
  std::vector<std::uint32_t> dequeued_;
  std::vector<std::pair<std::uint32_t, std::int32_t>> controls_set_;
};

}  // namespace luxloc::test
