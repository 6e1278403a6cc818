#include "plugins/v4l2/v4l2_camera_source.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

constexpr const char* kBadFrame = "bad frame";
constexpr int kPollMs = 200;  // a blocked next() re-checks the stop flag this often anyway

int positive_int(const SourceSpec& spec, const std::string& key, int fallback, int max) {
  const double v = spec.get_number(key, fallback);
  if (v != std::floor(v) || v < 1 || v > max)
    throw InputError("--source", 0, key, "'" + spec.text + "': " + key + " must be a whole number in 1.." +
                                             std::to_string(max));
  return static_cast<int>(v);
}

}  // namespace

V4l2CameraOptions v4l2_options_from_spec(const SourceSpec& spec) {
  static const char* known[] = {"width", "height", "fps", "exposure_us", "gain", "format", "buffers"};
  for (const auto& [key, value] : spec.params) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok)
      throw InputError("--source", 0, key,
                       "'" + spec.text + "': unknown option for v4l2 (known: width, height, fps, exposure_us, gain, "
                                         "format, buffers)");
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
  if (spec.params.count("format")) {
    try {
      o.format = parse_pixel_format(spec.get("format", ""));
    } catch (const std::invalid_argument& e) {
      throw InputError("--source", 0, "format", "'" + spec.text + "': " + e.what());
    }
  }
  return o;
}

V4l2CameraSource::V4l2CameraSource(V4l2CameraOptions options) {
  int fds[2];
  if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("cannot create the wake-up pipe");
  wake_read_.reset(fds[0]);
  wake_write_.reset(fds[1]);
  camera_ = std::make_unique<V4l2Camera>(std::move(options));
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

bool V4l2CameraSource::next(SensorData& out) {
  while (!stop_.load() && !lost_) {
    FrameSample f;
    V4l2Camera::GrabStatus s;
    try {
      s = camera_->grab(kPollMs, wake_read_.get(), f.gray, f.t);
    } catch (const V4l2Error& e) {
      std::lock_guard lock(failure_mutex_);
      failure_ = name() + ": " + e.what();
      lost_ = true;
      return false;
    }
    if (s == V4l2Camera::GrabStatus::bad_frame) {
      drops().add(kBadFrame, name() + ": " + camera_->last_error());
      continue;
    }
    if (s != V4l2Camera::GrabStatus::frame) continue;
    if (f.t <= last_t_) {  // a driver repeating a stamp: keep the stream strictly increasing
      drops().add("out of order", name() + ": frame time did not advance");
      continue;
    }
    last_t_ = f.t;
    ++frames_;
    if (camera_->arrival_stamped() && !warned_arrival_) {
      warned_arrival_ = true;
      std::fprintf(stderr,
                   "luxloc: %s: the driver gives no CLOCK_MONOTONIC buffer timestamps; frames are stamped on "
                   "arrival (late by readout + transfer: correct with --clock-offset)\n",
                   name().c_str());
    }
    out = std::move(f);
    return true;
  }
  return false;
}

SourcePtr make_v4l2_camera_source(const SourceSpec& spec) {
  auto src = std::make_unique<V4l2CameraSource>(v4l2_options_from_spec(spec));
  const V4l2Camera& c = src->camera();
  std::fprintf(stderr, "luxloc: %s: %s (%s), %s %dx%d, %.2f fps, exposure %s\n", src->name().c_str(), c.card().c_str(),
               c.driver().c_str(), pixel_format_name(c.format()).c_str(), c.width(), c.height(), c.fps(),
               c.exposure_us() ? (std::to_string(static_cast<int>(*c.exposure_us())) + " us").c_str() : "auto");
  for (const std::string& n : c.notes()) std::fprintf(stderr, "luxloc: %s: %s\n", src->name().c_str(), n.c_str());
  return src;
}

}  // namespace luxloc
