#include "plugins/v4l2/v4l2_camera_source.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/common/input_error.hpp"
#include "core/vlc/camera_model.hpp"
#include "plugins/serial/monotonic_clock.hpp"

namespace luxloc {
namespace {

constexpr const char* kBadFrame = "bad frame";
constexpr const char* kDeviceLost = "device lost";

int positive_int(const SourceSpec& spec, const std::string& key, int fallback, int max) {
  const double v = spec.get_number(key, fallback);
  if (v != std::floor(v) || v < 1 || v > max)
    throw InputError("--source", 0, key, "'" + spec.text + "': " + key + " must be a whole number in 1.." +
                                             std::to_string(max));
  return static_cast<int>(v);
}

}  // namespace

V4l2CameraOptions v4l2_options_from_spec(const SourceSpec& spec) {
  static const char* known[] = {"width", "height", "fps", "exposure_us", "gain", "format", "buffers", "on_loss", "row_time_us"};
  for (const auto& [key, value] : spec.params) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok)
      throw InputError("--source", 0, key,
                       "'" + spec.text + "': unknown option for v4l2 (known: width, height, fps, exposure_us, gain, "
                                         "format, buffers, on_loss, row_time_us)");
  }
  if (spec.target.rfind("/dev/", 0) != 0)
    throw InputError("--source", 0, "--source", "'" + spec.text + "': the v4l2 target is a device path such as /dev/video0");
  V4l2CameraOptions o;
  o.path = spec.target;
  o.width = positive_int(spec, "width", o.width, 16384);
  o.height = positive_int(spec, "height", o.height, 16384);
  o.buffers = positive_int(spec, "buffers", o.buffers, 32);
  o.fps = spec.get_number("fps", o.fps);
  if (!(o.fps > 0.0 && o.fps <= 1000.0))
    throw InputError("--source", 0, "fps", "'" + spec.text + "': fps must be in (0, 1000]");
  const std::string exposure = spec.get("exposure_us", "");
  if (exposure == "auto") {
    o.exposure_us.reset();
  } else if (!exposure.empty()) {
    o.exposure_us = spec.get_number("exposure_us", 0.0);
    if (!(*o.exposure_us > 0.0))
      throw InputError("--source", 0, "exposure_us", "'" + spec.text + "': exposure_us must be > 0 (or auto)");
  }
  if (spec.params.count("gain")) {
    o.gain = spec.get_number("gain", 0.0);
    if (*o.gain < 0.0) throw InputError("--source", 0, "gain", "'" + spec.text + "': gain must be >= 0");
  }
  if (spec.params.count("row_time_us")) {
    // The camera file's bounds (CameraModel::plausible_row_time_us): outside, a typo (ns, ms).
    o.row_time_us = spec.get_number("row_time_us", 0.0);
    if (!CameraModel::plausible_row_time_us(*o.row_time_us))
      throw InputError("--source", 0, "row_time_us", "'" + spec.text + "': row_time_us must be 1-200 (microseconds per row)");
  }
  if (spec.params.count("format")) {
    try {
      o.format = parse_pixel_format(spec.get("format", ""));
    } catch (const std::invalid_argument& e) {
      throw InputError("--source", 0, "format", "'" + spec.text + "': " + e.what());
    }
  }
  return o;
}

V4l2LossOptions V4l2LossOptions::from_spec(const SourceSpec& spec) {
  V4l2LossOptions o;
  const std::string on_loss = spec.get("on_loss", "end");
  if (on_loss == "end")
    o.on_loss = OnLoss::end;
  else if (on_loss == "wait")
    o.on_loss = OnLoss::wait;
  else
    throw InputError("--source", 0, "on_loss", "'" + spec.text + "': on_loss must be end or wait");
  return o;
}

V4l2CameraSource::V4l2CameraSource(V4l2CameraOptions options, V4l2LossOptions loss, std::shared_ptr<V4l2Io> io)
    : options_(std::move(options)), loss_(loss), io_(io ? std::move(io) : libv4l2_io()) {
  int fds[2];
  if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("cannot create the wake-up pipe");
  wake_read_.reset(fds[0]);
  wake_write_.reset(fds[1]);
  camera_ = std::make_unique<V4l2Camera>(options_, io_);
  last_frame_arrival_ = monotonic_now_ns();
}

void V4l2CameraSource::request_stop() {
  stop_.store(true);
  const char b = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_write_.get(), &b, 1);
}

std::string V4l2CameraSource::failure() const {
  std::lock_guard lock(failure_mutex_);
  return failure_;
}

bool V4l2CameraSource::reopen() {
  camera_.reset();  // unmaps and closes the lost device
  while (!stop_.load()) {
    pollfd p{wake_read_.get(), POLLIN, 0};
    ::poll(&p, 1, static_cast<int>(loss_.reopen_interval_s * 1000));
    if (stop_.load()) break;
    try {
      camera_ = std::make_unique<V4l2Camera>(options_, io_);
      if (loss_.report_to_stderr) std::fprintf(stderr, "luxloc: %s: device is back\n", name().c_str());
      last_frame_arrival_ = monotonic_now_ns();
      warned_silent_ = false;
      return true;
    } catch (const V4l2Error&) {
      // Not back yet (or busy): try again after the interval.
    }
  }
  return false;
}

bool V4l2CameraSource::next(SensorData& out) {
  while (!stop_.load() && !lost_) {
    FrameSample f;
    V4l2Camera::GrabStatus s;
    try {
      s = camera_->grab(loss_.poll_timeout_ms, wake_read_.get(), f.gray, f.t);
    } catch (const V4l2Error& e) {
      ++losses_;
      const std::string what = name() + ": " + e.what();
      if (loss_.on_loss == OnLoss::wait) {
        drops().add(kDeviceLost, what);
        if (loss_.report_to_stderr)
          std::fprintf(stderr, "luxloc: %s; waiting for it to come back\n", what.c_str());
        if (reopen()) continue;
        return false;
      }
      std::lock_guard lock(failure_mutex_);
      failure_ = what;
      lost_ = true;
      camera_.reset();
      return false;
    }
    if (s == V4l2Camera::GrabStatus::timeout) {
      ++timeouts_;
      if (!warned_silent_ && loss_.report_to_stderr &&
          monotonic_now_ns() - last_frame_arrival_ > seconds_to_ns(loss_.silent_warn_s)) {
        warned_silent_ = true;
        std::fprintf(stderr, "luxloc: %s: no frame for %.1f s (the camera sends nothing); waiting\n", name().c_str(),
                     loss_.silent_warn_s);
      }
      continue;
    }
    if (s == V4l2Camera::GrabStatus::bad_frame) {
      drops().add(kBadFrame, name() + ": " + camera_->last_error());
      continue;
    }
    if (s != V4l2Camera::GrabStatus::frame) continue;
    last_frame_arrival_ = monotonic_now_ns();
    warned_silent_ = false;
    if (f.t <= last_t_) {  // a driver repeating a stamp: keep the stream strictly increasing
      drops().add("out of order", name() + ": frame time did not advance");
      continue;
    }
    last_t_ = f.t;
    ++frames_;
    if (camera_->arrival_stamped() && !warned_arrival_) {
      warned_arrival_ = true;
      if (loss_.report_to_stderr)
        std::fprintf(stderr,
                     "luxloc: %s: the driver gives no usable buffer timestamps; frames are stamped on "
                     "arrival (late by readout + transfer: correct with --clock-offset)\n",
                     name().c_str());
    }
    if (camera_->end_of_frame_stamped() && !warned_end_of_frame_) {
      warned_end_of_frame_ = true;
      if (loss_.report_to_stderr) {
        const TimeNs shift = camera_->end_of_frame_shift_ns();
        if (shift > 0)
          std::fprintf(stderr,
                       "luxloc: %s: the driver stamps the end of each frame; frames moved back by %.2f ms (%d rows x "
                       "%.1f us + exposure %s) to row 0's exposure start\n",
                       name().c_str(), 1e-6 * static_cast<double>(shift), camera_->height() - 1,
                       *camera_->options().row_time_us,
                       camera_->exposure_us() ? (std::to_string(static_cast<int>(*camera_->exposure_us())) + " us").c_str()
                                              : "auto, not counted");
        else
          std::fprintf(stderr,
                       "luxloc: %s: the driver stamps the end of each frame: frames are late by their readout; give "
                       "row_time_us= (or --camera with row_time_us) to move them to row 0's exposure start\n",
                       name().c_str());
      }
    }
    out = std::move(f);
    return true;
  }
  return false;
}

SourcePtr make_v4l2_camera_source(const SourceSpec& spec) {
  auto src = std::make_unique<V4l2CameraSource>(v4l2_options_from_spec(spec), V4l2LossOptions::from_spec(spec));
  const V4l2Camera& c = src->camera();
  std::fprintf(stderr, "luxloc: %s: %s (%s), %s %dx%d, %.2f fps, exposure %s\n", src->name().c_str(), c.card().c_str(),
               c.driver().c_str(), pixel_format_name(c.format()).c_str(), c.width(), c.height(), c.fps(),
               c.exposure_us() ? (std::to_string(static_cast<int>(*c.exposure_us())) + " us").c_str() : "auto");
  for (const std::string& n : c.notes()) std::fprintf(stderr, "luxloc: %s: %s\n", src->name().c_str(), n.c_str());
  return src;
}

}  // namespace luxloc
