#include "plugins/v4l2/v4l2_camera.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "plugins/serial/monotonic_clock.hpp"
#include "plugins/v4l2/buffer_time.hpp"

namespace luxloc {
namespace {

std::string errno_text(int e) { return std::string(std::strerror(e)) + " (errno " + std::to_string(e) + ")"; }

std::string cstr(const unsigned char* s, std::size_t n) {
  std::size_t len = 0;
  while (len < n && s[len] != 0) ++len;
  return std::string(reinterpret_cast<const char*>(s), len);
}

std::string format_size(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

std::vector<V4l2Control> query_controls(int fd) { return query_controls(*libv4l2_io(), fd); }

std::vector<V4l2Control> query_controls(V4l2Io& io, int fd) {
  std::vector<V4l2Control> out;
  v4l2_queryctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
  while (io.ioctl(fd, VIDIOC_QUERYCTRL, &q) == 0) {
    const std::uint32_t id = q.id;
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
    if ((q.flags & V4L2_CTRL_FLAG_DISABLED) || q.type == V4L2_CTRL_TYPE_CTRL_CLASS) continue;
    V4l2Control c;
    c.id = id;
    c.name = cstr(q.name, sizeof q.name);
    c.ctl_name = v4l2_control_name(c.name);
    c.type = q.type;
    c.range = {q.minimum, q.maximum, q.step, q.default_value};
    c.inactive = (q.flags & V4L2_CTRL_FLAG_INACTIVE) != 0;
    if (!(q.flags & V4L2_CTRL_FLAG_WRITE_ONLY)) {
      v4l2_control v{};
      v.id = id;
      if (io.ioctl(fd, VIDIOC_G_CTRL, &v) == 0) {
        c.value = v.value;
        c.readable = true;
      }
    }
    if (q.type == V4L2_CTRL_TYPE_MENU) {
      for (std::int32_t i = q.minimum; i <= q.maximum; ++i) {
        v4l2_querymenu m{};
        m.id = id;
        m.index = static_cast<std::uint32_t>(i);
        if (io.ioctl(fd, VIDIOC_QUERYMENU, &m) == 0) c.menu.emplace_back(i, cstr(m.name, sizeof m.name));
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::string describe_controls(const std::vector<V4l2Control>& controls) {
  std::string s;
  for (const V4l2Control& c : controls) {
    if (!s.empty()) s += ", ";
    s += c.ctl_name + " (" + std::to_string(c.range.minimum) + ".." + std::to_string(c.range.maximum) + ")";
  }
  return s.empty() ? "none" : s;
}

V4l2Camera::V4l2Camera(V4l2CameraOptions options, std::shared_ptr<V4l2Io> io)
    : options_(std::move(options)), io_(io ? std::move(io) : libv4l2_io()) {
  try {
    open_device();
    negotiate_format();
    set_frame_rate();
    set_exposure_and_gain();
    start_streaming();
  } catch (...) {
    stop_streaming();
    if (fd_ >= 0) io_->close(fd_);
    fd_ = -1;
    throw;
  }
}

V4l2Camera::~V4l2Camera() {
  stop_streaming();
  if (fd_ >= 0) io_->close(fd_);
}

int V4l2Camera::xioctl(unsigned long request, void* arg) const {
  int r;
  do {
    r = io_->ioctl(fd_, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

void V4l2Camera::open_device() {
  const std::string& path = options_.path;
  // Plain open() and VIDIOC_QUERYCAP first, then libv4l2 takes the descriptor over
  // (v4l2_fd_open): a file that is no V4L2 device gets our message, not libv4l2's.
  const int raw = io_->open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (raw < 0) {
    const int e = errno;
    if (e == ENOENT || e == ENODEV || e == ENXIO)
      throw V4l2Error(V4l2Error::Kind::no_device,
                      path + ": no such device (is the camera plugged in? `luxloc devices` lists the cameras): " +
                          errno_text(e));
    if (e == EACCES || e == EPERM)
      throw V4l2Error(V4l2Error::Kind::permission,
                      path + ": permission denied (add the user to the 'video' group): " + errno_text(e));
    if (e == EBUSY)
      throw V4l2Error(V4l2Error::Kind::busy, path + ": device busy (another program is using the camera)");
    throw V4l2Error(V4l2Error::Kind::io, path + ": cannot open: " + errno_text(e));
  }
  v4l2_capability cap{};
  int r;
  do {
    r = io_->ioctl(raw, VIDIOC_QUERYCAP, &cap);
  } while (r == -1 && errno == EINTR);
  if (r != 0) {
    const int e = errno;
    io_->close(raw);
    throw V4l2Error(V4l2Error::Kind::not_capture,
                    path + ": not a V4L2 device (VIDIOC_QUERYCAP failed: " + errno_text(e) + ")");
  }
  fd_ = io_->fd_open(raw);
  if (fd_ < 0) {
    const int e = errno;
    io_->close(raw);
    throw V4l2Error(V4l2Error::Kind::io, path + ": libv4l2 cannot take the device over: " + errno_text(e));
  }
  driver_ = cstr(cap.driver, sizeof cap.driver);
  card_ = cstr(cap.card, sizeof cap.card);
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE))
    throw V4l2Error(V4l2Error::Kind::not_capture,
                    path + " (" + card_ + ", " + driver_ +
                        "): not a video capture device (UVC cameras also create a metadata node; try the other "
                        "/dev/videoN, see `luxloc devices`)");
  if (!(caps & V4L2_CAP_STREAMING))
    throw V4l2Error(V4l2Error::Kind::not_capture, path + " (" + card_ + "): no streaming I/O (mmap) support");
}

void V4l2Camera::negotiate_format() {
  // Native formats (libv4l2 adds emulated ones, converted in software: not wanted).
  std::vector<std::uint32_t> native, all;
  v4l2_fmtdesc d{};
  d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (d.index = 0; xioctl(VIDIOC_ENUM_FMT, &d) == 0; ++d.index) {
    all.push_back(d.pixelformat);
    if (!(d.flags & V4L2_FMT_FLAG_EMULATED)) native.push_back(d.pixelformat);
  }
  const auto has = [&](std::uint32_t f) {
    for (std::uint32_t x : native)
      if (x == f || (f == V4L2_PIX_FMT_MJPEG && x == V4L2_PIX_FMT_JPEG)) return x;
    return 0u;
  };
  std::string offered;
  for (std::uint32_t f : all) {
    if (!offered.empty()) offered.append(" ");
    offered.append(fourcc_text(f));
  }
  std::uint32_t chosen = 0;
  if (options_.format) {
    chosen = has(pixel_format_fourcc(*options_.format));
    if (!chosen)
      throw V4l2Error(V4l2Error::Kind::unsupported_format,
                      options_.path + ": format " + pixel_format_name(*options_.format) + " (" +
                          fourcc_text(pixel_format_fourcc(*options_.format)) +
                          ") is not offered by the camera (it offers: " + (offered.empty() ? "none" : offered) + ")");
  } else {
    for (PixelFormat f : {PixelFormat::grey, PixelFormat::yuyv, PixelFormat::mjpeg})
      if ((chosen = has(pixel_format_fourcc(f))) != 0) break;
    if (!chosen)
      throw V4l2Error(V4l2Error::Kind::unsupported_format,
                      options_.path + ": the camera offers none of GREY, YUYV, MJPEG (it offers: " +
                          (offered.empty() ? "none" : offered) + ")");
  }
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<std::uint32_t>(options_.width);
  fmt.fmt.pix.height = static_cast<std::uint32_t>(options_.height);
  fmt.fmt.pix.pixelformat = chosen;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(VIDIOC_S_FMT, &fmt) != 0) {
    const int e = errno;
    if (e == EBUSY)
      throw V4l2Error(V4l2Error::Kind::busy,
                      options_.path + ": device busy (another program is streaming from the camera)");
    throw V4l2Error(V4l2Error::Kind::unsupported_format, options_.path + ": VIDIOC_S_FMT " + fourcc_text(chosen) + " " +
                                                             format_size(options_.width, options_.height) +
                                                             " failed: " + errno_text(e));
  }
  // The driver may set another format than asked for (VIDIOC_S_FMT never fails for that):
  // one we convert is taken with a note, unless the user named the format.
  const auto got = pixel_format_from_fourcc(fmt.fmt.pix.pixelformat);
  if (!got || (options_.format && *got != *options_.format))
    throw V4l2Error(V4l2Error::Kind::unsupported_format,
                    options_.path + ": asked for " + fourcc_text(chosen) + ", the driver set " +
                        fourcc_text(fmt.fmt.pix.pixelformat) +
                        (got ? "" : " (not one of GREY, YUYV, MJPEG: it cannot be converted)"));
  if (fmt.fmt.pix.pixelformat != chosen && !(pixel_format_from_fourcc(chosen) == got))
    notes_.push_back("asked for " + fourcc_text(chosen) + ", the driver set " + fourcc_text(fmt.fmt.pix.pixelformat));
  format_ = *got;
  layout_.width = static_cast<int>(fmt.fmt.pix.width);
  layout_.height = static_cast<int>(fmt.fmt.pix.height);
  layout_.bytes_per_line = static_cast<int>(fmt.fmt.pix.bytesperline);
  if (layout_.width != options_.width || layout_.height != options_.height)
    notes_.push_back("asked for " + format_size(options_.width, options_.height) + ", the camera set " +
                     format_size(layout_.width, layout_.height) + " (camera.yaml must match this mode)");
}

void V4l2Camera::set_frame_rate() {
  v4l2_streamparm p{};
  p.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(VIDIOC_G_PARM, &p) != 0 || !(p.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
    notes_.push_back("the driver does not let the frame rate be set; it runs at its default");
    return;
  }
  // timeperframe is a fraction of seconds: 1/fps, kept exact for integer and 1001-based rates.
  const double fps = options_.fps;
  if (std::abs(fps - std::round(fps)) < 1e-6) {
    p.parm.capture.timeperframe = {1, static_cast<std::uint32_t>(std::lround(fps))};
  } else {
    p.parm.capture.timeperframe = {1000, static_cast<std::uint32_t>(std::lround(fps * 1000.0))};
  }
  if (xioctl(VIDIOC_S_PARM, &p) != 0) {
    notes_.push_back("VIDIOC_S_PARM failed (" + errno_text(errno) + "); frame rate left at the default");
    return;
  }
  const v4l2_fract& tpf = p.parm.capture.timeperframe;
  if (tpf.numerator > 0) fps_ = static_cast<double>(tpf.denominator) / tpf.numerator;
  if (fps_ > 0 && std::abs(fps_ - fps) > 0.01 * fps) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "asked for %.2f fps, the camera set %.2f fps", fps, fps_);
    notes_.emplace_back(buf);
  }
}

void V4l2Camera::set_exposure_and_gain() {
  if (!options_.exposure_us && !options_.gain) return;
  const std::vector<V4l2Control> controls = query_controls(*io_, fd_);
  const auto find = [&](std::uint32_t id, bool (*by_name)(std::string_view)) -> const V4l2Control* {
    for (const V4l2Control& c : controls)
      if (c.id == id) return &c;
    if (by_name)  // a driver exposing the control under a private id but the usual name
      for (const V4l2Control& c : controls)
        if (by_name(c.name)) return &c;
    return nullptr;
  };
  const auto set = [&](const V4l2Control& c, std::int32_t value) {
    v4l2_control v{};
    v.id = c.id;
    v.value = value;
    if (xioctl(VIDIOC_S_CTRL, &v) != 0)
      throw V4l2Error(V4l2Error::Kind::no_manual_exposure, options_.path + ": setting " + c.ctl_name + " = " +
                                                               std::to_string(value) + " failed: " +
                                                               errno_text(errno));
  };

  if (options_.exposure_us) {
    const V4l2Control* abs = find(V4L2_CID_EXPOSURE_ABSOLUTE, &is_exposure_absolute_name);
    if (!abs)
      throw V4l2Error(V4l2Error::Kind::no_manual_exposure,
                      options_.path + " (" + card_ + "): no manual exposure control (neither exposure_time_absolute "
                                      "nor exposure_absolute); the camera's controls: " + describe_controls(controls) +
                                      ". Use exposure_us=auto to run with the camera's own exposure.");
    // Auto exposure off first: while it is on, the absolute exposure is inactive / ignored.
    if (const V4l2Control* ae = find(V4L2_CID_EXPOSURE_AUTO, &is_auto_exposure_name)) {
      std::int32_t manual = V4L2_EXPOSURE_MANUAL;
      bool has_manual = ae->menu.empty();
      for (const auto& [index, name] : ae->menu) has_manual = has_manual || index == V4L2_EXPOSURE_MANUAL;
      if (!has_manual) {
        // Some UVC cameras offer only "Aperture Priority" (3) besides auto; shutter priority
        // (2) also takes a manual exposure time.
        for (const auto& [index, name] : ae->menu)
          if (index == V4L2_EXPOSURE_SHUTTER_PRIORITY) {
            manual = index;
            has_manual = true;
          }
      }
      if (!has_manual) {
        std::string modes;
        for (const auto& [index, name] : ae->menu) {
          if (!modes.empty()) modes.append(", ");
          modes.append(std::to_string(index)).append(" ").append(name);
        }
        throw V4l2Error(V4l2Error::Kind::no_manual_exposure,
                        options_.path + ": " + ae->ctl_name + " has no manual mode (modes: " + modes + ")");
      }
      set(*ae, manual);
    }
    // The exposure must not stretch the frame interval (or lengthen itself in the dark).
    if (const V4l2Control* dyn = find(V4L2_CID_EXPOSURE_AUTO_PRIORITY, &is_exposure_dynamic_framerate_name))
      set(*dyn, 0);
    const ExposureUnits units = exposure_us_to_units(*options_.exposure_us, abs->range);
    if (units.adjusted) notes_.push_back(units.message);
    set(*abs, units.units);
    v4l2_control v{};
    v.id = abs->id;
    if (xioctl(VIDIOC_G_CTRL, &v) == 0) {
      // What the driver really set: it may clamp further than the range it reports (to the
      // frame interval) or ignore the value (auto exposure still on).
      exposure_us_ = exposure_units_to_us(v.value);
      if (v.value != units.units) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "%s: set %d (%.0f us), the camera reads back %d (%.0f us)%s",
                      abs->ctl_name.c_str(), units.units, units.applied_us, v.value, *exposure_us_,
                      v.value == abs->value ? ": it ignored the setting" : ": it clamped it");
        notes_.emplace_back(buf);
      }
    } else {
      exposure_us_ = units.applied_us;
    }
    if (fps_ > 0 && *exposure_us_ > 1e6 / fps_)
      notes_.push_back("the exposure is longer than the frame interval: the camera caps it or lowers the frame rate");
  }
  if (options_.gain) {
    const V4l2Control* g = find(V4L2_CID_GAIN, nullptr);
    if (!g) {
      notes_.push_back("the camera has no gain control (V4L2_CID_GAIN); gain=" + std::to_string(*options_.gain) +
                       " ignored");
    } else {
      const double wanted = *options_.gain;
      const std::int32_t value = static_cast<std::int32_t>(
          std::lround(std::clamp(wanted, static_cast<double>(g->range.minimum), static_cast<double>(g->range.maximum))));
      if (value != wanted)
        notes_.push_back("gain " + std::to_string(wanted) + " outside " + std::to_string(g->range.minimum) + ".." +
                         std::to_string(g->range.maximum) + ": set to " + std::to_string(value));
      set(*g, value);
    }
  }
}

void V4l2Camera::start_streaming() {
  v4l2_requestbuffers req{};
  req.count = static_cast<std::uint32_t>(std::max(options_.buffers, 2));
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(VIDIOC_REQBUFS, &req) != 0) {
    const int e = errno;
    if (e == EBUSY)
      throw V4l2Error(V4l2Error::Kind::busy, options_.path + ": device busy (another program holds its buffers)");
    throw V4l2Error(V4l2Error::Kind::io, options_.path + ": VIDIOC_REQBUFS (mmap) failed: " + errno_text(e));
  }
  if (req.count < 2) throw V4l2Error(V4l2Error::Kind::io, options_.path + ": the driver granted fewer than 2 buffers");
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (xioctl(VIDIOC_QUERYBUF, &b) != 0)
      throw V4l2Error(V4l2Error::Kind::io, options_.path + ": VIDIOC_QUERYBUF failed: " + errno_text(errno));
    void* p = io_->mmap(b.length, fd_, b.m.offset);
    if (p == MAP_FAILED) throw V4l2Error(V4l2Error::Kind::io, options_.path + ": mmap failed: " + errno_text(errno));
    buffers_.push_back({p, b.length});
    if (xioctl(VIDIOC_QBUF, &b) != 0)
      throw V4l2Error(V4l2Error::Kind::io, options_.path + ": VIDIOC_QBUF failed: " + errno_text(errno));
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(VIDIOC_STREAMON, &type) != 0) {
    const int e = errno;
    throw V4l2Error(e == EBUSY ? V4l2Error::Kind::busy : V4l2Error::Kind::io,
                    options_.path + ": VIDIOC_STREAMON failed: " + errno_text(e));
  }
  streaming_ = true;
}

void V4l2Camera::stop_streaming() noexcept {
  if (streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    (void)xioctl(VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (const Buffer& b : buffers_) io_->munmap(b.start, b.length);
  buffers_.clear();
}

V4l2Camera::GrabStatus V4l2Camera::grab(int timeout_ms, int wake_fd, cv::Mat& gray, TimeNs& t) {
  pollfd p[2] = {{fd_, POLLIN, 0}, {wake_fd, POLLIN, 0}};
  const int n = io_->poll(p, wake_fd >= 0 ? 2 : 1, timeout_ms);
  if (n < 0) {
    if (errno == EINTR) return GrabStatus::timeout;
    throw V4l2Error(V4l2Error::Kind::io, options_.path + ": poll failed: " + errno_text(errno));
  }
  if (wake_fd >= 0 && (p[1].revents & POLLIN)) return GrabStatus::woken;
  if (n == 0) return GrabStatus::timeout;
  if (p[0].revents & (POLLERR | POLLHUP | POLLNVAL))
    throw V4l2Error(V4l2Error::Kind::io, options_.path + ": device lost (unplugged?)");
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (xioctl(VIDIOC_DQBUF, &b) != 0) {
    const int e = errno;
    if (e == EAGAIN) return GrabStatus::timeout;
    throw V4l2Error(V4l2Error::Kind::io, options_.path + ": device lost (VIDIOC_DQBUF: " + errno_text(e) + ")");
  }
  const TimeNs arrival = monotonic_now_ns();
  GrabStatus status = GrabStatus::frame;
  if (b.index >= buffers_.size() || (b.flags & V4L2_BUF_FLAG_ERROR)) {
    error_ = "the driver flagged the buffer as corrupt";
    status = GrabStatus::bad_frame;
  } else if (!to_gray8(format_, static_cast<const std::uint8_t*>(buffers_[b.index].start),
                       std::min<std::size_t>(b.bytesused, buffers_[b.index].length), layout_, gray, error_)) {
    status = GrabStatus::bad_frame;
  }
  timespec real{};
  clock_gettime(CLOCK_REALTIME, &real);
  const TimeNs stamp = static_cast<TimeNs>(b.timestamp.tv_sec) * kNsPerSecond +
                       static_cast<TimeNs>(b.timestamp.tv_usec) * 1000;
  const BufferTime bt = buffer_time(b.flags, stamp, arrival, static_cast<TimeNs>(real.tv_sec) * kNsPerSecond + real.tv_nsec);
  clock_ = bt.clock;
  arrival_stamped_ = bt.clock == BufferClock::arrival;
  end_of_frame_ = bt.end_of_frame;
  t = bt.t - (end_of_frame_ ? end_of_frame_shift_ns() : 0);
  if (xioctl(VIDIOC_QBUF, &b) != 0)
    throw V4l2Error(V4l2Error::Kind::io, options_.path + ": device lost (VIDIOC_QBUF: " + errno_text(errno) + ")");
  return status;
}

TimeNs V4l2Camera::end_of_frame_shift_ns() const {
  // End of frame = row 0's exposure start + the exposure + (H - 1) row times (the last row's
  // readout ends one exposure after it started, H - 1 rows after row 0).
  if (!options_.row_time_us) return 0;
  const double us = exposure_us_.value_or(0.0) + static_cast<double>(std::max(0, layout_.height - 1)) * *options_.row_time_us;
  return static_cast<TimeNs>(std::llround(us * 1000.0));
}

}  // namespace luxloc
