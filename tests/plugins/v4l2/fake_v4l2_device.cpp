#include "plugins/v4l2/fake_v4l2_device.hpp"

#include <sys/eventfd.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace luxloc::test {
namespace {

constexpr std::int64_t kOffsetStep = 1 << 20;  // QUERYBUF's m.offset of buffer i: i MiB

void copy_name(unsigned char* dst, std::size_t n, const std::string& s) {
  std::memset(dst, 0, n);
  std::memcpy(dst, s.data(), std::min(n - 1, s.size()));
}

std::uint32_t bytes_per_line(std::uint32_t fourcc, std::uint32_t width) {
  if (fourcc == V4L2_PIX_FMT_GREY) return width;
  if (fourcc == V4L2_PIX_FMT_YUYV) return 2 * width;
  if (fourcc == V4L2_PIX_FMT_RGB24) return 3 * width;
  return 0;  // compressed
}

}  // namespace

int FakeV4l2Device::fail(int err) const {
  errno = err;
  return -1;
}

bool FakeV4l2Device::lost(int fd) const {
  const auto it = fds_.find(fd);
  return it == fds_.end() || unplugged_ || it->second != generation_;
}

void FakeV4l2Device::set_ready(bool ready) {
  // The eventfd is readable (POLLIN) while a filled buffer waits for DQBUF.
  for (const auto& [fd, gen] : fds_) {
    if (ready) {
      const std::uint64_t one = 1;
      [[maybe_unused]] const ssize_t n = ::write(fd, &one, sizeof one);
    } else {
      std::uint64_t v = 0;
      [[maybe_unused]] const ssize_t n = ::read(fd, &v, sizeof v);
    }
  }
}

bool FakeV4l2Device::push_frame(const FakeFrame& f) {
  std::lock_guard lock(mutex_);
  if (!streaming_ || unplugged_ || queued_.empty()) {
    ++counts_.overruns;
    return false;
  }
  const std::uint32_t i = queued_.front();
  queued_.pop_front();
  Buffer& b = buffers_[i];
  std::fill(b.memory.begin(), b.memory.end(), 0);
  std::memcpy(b.memory.data(), f.bytes.data(), std::min(f.bytes.size(), b.memory.size()));
  b.info.bytesused = std::min<std::uint32_t>(f.bytesused.value_or(static_cast<std::uint32_t>(f.bytes.size())),
                                             static_cast<std::uint32_t>(b.memory.size()));
  b.info.flags = f.clock_flags | V4L2_BUF_FLAG_DONE | (f.error ? V4L2_BUF_FLAG_ERROR : 0u);
  b.info.timestamp.tv_sec = static_cast<time_t>(f.stamp_ns / kNsPerSecond);
  b.info.timestamp.tv_usec = static_cast<suseconds_t>((f.stamp_ns % kNsPerSecond) / 1000);
  b.info.sequence = sequence_++;
  b.state = BufState::done;
  done_.push_back(i);
  set_ready(true);
  return true;
}

void FakeV4l2Device::unplug() {
  std::lock_guard lock(mutex_);
  unplugged_ = true;
  set_ready(true);  // wake a poll in progress: it then reports POLLERR
}

void FakeV4l2Device::replug() {
  std::lock_guard lock(mutex_);
  unplugged_ = false;
  ++generation_;  // descriptors of the old device stay dead
  buffers_.clear();
  queued_.clear();
  done_.clear();
  streaming_ = false;
}

FakeV4l2Device::Counts FakeV4l2Device::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

std::vector<std::uint32_t> FakeV4l2Device::dequeued() const {
  std::lock_guard lock(mutex_);
  return dequeued_;
}

std::vector<std::pair<std::uint32_t, std::int32_t>> FakeV4l2Device::controls_set() const {
  std::lock_guard lock(mutex_);
  return controls_set_;
}

std::optional<FakeControl> FakeV4l2Device::control(std::uint32_t id) const {
  std::lock_guard lock(mutex_);
  for (const FakeControl& c : controls)
    if (c.id == id) return c;
  return std::nullopt;
}

v4l2_pix_format FakeV4l2Device::format() const {
  std::lock_guard lock(mutex_);
  return fmt_;
}

int FakeV4l2Device::open(const std::string&, int) {
  std::lock_guard lock(mutex_);
  if (unplugged_) return fail(ENODEV);
  if (open_errno != 0) return fail(open_errno);
  const int fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (fd < 0) return -1;
  fds_[fd] = generation_;
  ++counts_.opens;
  return fd;
}

int FakeV4l2Device::close(int fd) {
  std::lock_guard lock(mutex_);
  const auto it = fds_.find(fd);
  if (it == fds_.end()) return fail(EBADF);
  if (it->second == generation_ && !unplugged_) {
    // Closing the streaming descriptor stops the stream and frees the buffers (as the kernel does).
    streaming_ = false;
    buffers_.clear();
    queued_.clear();
    done_.clear();
  }
  fds_.erase(it);
  ::close(fd);
  ++counts_.closes;
  return 0;
}

void* FakeV4l2Device::mmap(std::size_t length, int fd, std::int64_t offset) {
  std::lock_guard lock(mutex_);
  const std::size_t i = static_cast<std::size_t>(offset / kOffsetStep);
  if (lost(fd) || offset % kOffsetStep != 0 || i >= buffers_.size() || length != buffers_[i].memory.size()) {
    errno = lost(fd) ? ENODEV : EINVAL;
    return MAP_FAILED;
  }
  ++counts_.mapped;
  return buffers_[i].memory.data();
}

int FakeV4l2Device::munmap(void*, std::size_t) {
  std::lock_guard lock(mutex_);
  --counts_.mapped;
  return 0;
}

int FakeV4l2Device::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  const int n = ::poll(fds, count, timeout_ms);
  if (n < 0) return n;
  std::lock_guard lock(mutex_);
  int ready = 0;
  for (nfds_t k = 0; k < count; ++k) {
    if (fds_.count(fds[k].fd)) {
      if (lost(fds[k].fd)) fds[k].revents = POLLERR | POLLHUP;  // the device node is gone
    }
    if (fds[k].revents != 0) ++ready;
  }
  return ready;
}

int FakeV4l2Device::ioctl(int fd, unsigned long request, void* arg) {
  std::lock_guard lock(mutex_);
  if (lost(fd)) return fail(ENODEV);
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      *cap = {};
      copy_name(cap->driver, sizeof cap->driver, "fakecam");
      copy_name(cap->card, sizeof cap->card, "Fake Camera");
      cap->capabilities = caps | V4L2_CAP_DEVICE_CAPS;
      cap->device_caps = caps;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* d = static_cast<v4l2_fmtdesc*>(arg);
      if (d->index >= formats.size()) return fail(EINVAL);
      d->pixelformat = formats[d->index];
      d->flags = d->pixelformat == V4L2_PIX_FMT_MJPEG ? V4L2_FMT_FLAG_COMPRESSED : 0u;
      return 0;
    }
    case VIDIOC_S_FMT: {
      if (s_fmt_errno != 0) return fail(s_fmt_errno);
      if (streaming_) return fail(EBUSY);
      auto* f = static_cast<v4l2_format*>(arg);
      v4l2_pix_format& p = f->fmt.pix;
      if (std::find(formats.begin(), formats.end(), p.pixelformat) == formats.end()) p.pixelformat = formats.front();
      if (adjust_format) adjust_format(p);
      p.bytesperline = bytes_per_line(p.pixelformat, p.width);
      p.sizeimage = p.bytesperline ? p.bytesperline * p.height : p.width * p.height;  // MJPEG: room for any frame
      p.field = V4L2_FIELD_NONE;
      fmt_ = p;
      return 0;
    }
    case VIDIOC_G_PARM:
    case VIDIOC_S_PARM: {
      auto* s = static_cast<v4l2_streamparm*>(arg);
      if (request == VIDIOC_S_PARM) {
        timeperframe_ = s->parm.capture.timeperframe;
        if (actual_fps > 0) timeperframe_ = {1000, static_cast<std::uint32_t>(actual_fps * 1000 + 0.5)};
      }
      s->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
      s->parm.capture.timeperframe = timeperframe_;
      return 0;
    }
    case VIDIOC_QUERYCTRL:
    case VIDIOC_G_CTRL:
    case VIDIOC_S_CTRL:
    case VIDIOC_QUERYMENU:
      return control_ioctl(request, arg);
    case VIDIOC_REQBUFS:
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF:
    case VIDIOC_DQBUF:
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF:
      return buffer_ioctl(request, arg);
    default:
      return fail(ENOTTY);
  }
}

int FakeV4l2Device::control_ioctl(unsigned long request, void* arg) {
  std::vector<FakeControl*> sorted;
  for (FakeControl& c : controls) sorted.push_back(&c);
  std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->id < b->id; });
  const auto find = [&](std::uint32_t id) -> FakeControl* {
    for (FakeControl* c : sorted)
      if (c->id == id) return c;
    return nullptr;
  };
  if (request == VIDIOC_QUERYCTRL) {
    auto* q = static_cast<v4l2_queryctrl*>(arg);
    FakeControl* c = nullptr;
    if (q->id & V4L2_CTRL_FLAG_NEXT_CTRL) {
      const std::uint32_t after = q->id & ~V4L2_CTRL_FLAG_NEXT_CTRL;
      for (FakeControl* x : sorted)
        if (x->id > after) {
          c = x;
          break;
        }
    } else {
      c = find(q->id);
    }
    if (!c) return fail(EINVAL);
    *q = {};
    q->id = c->id;
    q->type = c->type;
    copy_name(q->name, sizeof q->name, c->name);
    q->minimum = c->minimum;
    q->maximum = c->maximum;
    q->step = c->step;
    q->default_value = c->default_value;
    return 0;
  }
  if (request == VIDIOC_QUERYMENU) {
    auto* m = static_cast<v4l2_querymenu*>(arg);
    FakeControl* c = find(m->id);
    if (!c || !c->menu.count(static_cast<std::int32_t>(m->index))) return fail(EINVAL);
    copy_name(m->name, sizeof m->name, c->menu.at(static_cast<std::int32_t>(m->index)));
    return 0;
  }
  auto* v = static_cast<v4l2_control*>(arg);
  FakeControl* c = find(v->id);
  if (!c) return fail(EINVAL);
  if (request == VIDIOC_G_CTRL) {
    v->value = c->value;
    return 0;
  }
  controls_set_.emplace_back(v->id, v->value);
  if (c->type == V4L2_CTRL_TYPE_MENU && !c->menu.count(v->value)) return fail(EINVAL);
  switch (c->behaviour) {
    case FakeControl::Behaviour::accept:
      c->value = std::clamp(v->value, c->minimum, c->maximum);
      break;
    case FakeControl::Behaviour::clamp:
      c->value = std::clamp(v->value, c->minimum, std::min(c->maximum, c->clamp_max));
      break;
    case FakeControl::Behaviour::ignore:
      break;
  }
  return 0;
}

int FakeV4l2Device::buffer_ioctl(unsigned long request, void* arg) {
  if (request == VIDIOC_STREAMON || request == VIDIOC_STREAMOFF) {
    if (request == VIDIOC_STREAMON) {
      if (buffers_.empty()) return fail(EINVAL);
      streaming_ = true;
      ++counts_.streamons;
    } else {
      streaming_ = false;
      ++counts_.streamoffs;
      // STREAMOFF returns every buffer to the application (dequeued state).
      queued_.clear();
      done_.clear();
      for (Buffer& b : buffers_) b.state = BufState::idle;
      set_ready(false);
    }
    return 0;
  }
  if (request == VIDIOC_REQBUFS) {
    auto* r = static_cast<v4l2_requestbuffers*>(arg);
    if (r->memory != V4L2_MEMORY_MMAP) return fail(EINVAL);
    if (streaming_ || counts_.mapped > 0) return fail(EBUSY);
    buffers_.assign(std::min<std::uint32_t>(r->count, 8), Buffer{});
    for (std::uint32_t i = 0; i < buffers_.size(); ++i) {
      buffers_[i].memory.assign(fmt_.sizeimage, 0);
      buffers_[i].info.index = i;
      buffers_[i].info.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buffers_[i].info.memory = V4L2_MEMORY_MMAP;
      buffers_[i].info.length = fmt_.sizeimage;
      buffers_[i].info.m.offset = static_cast<std::uint32_t>(i * kOffsetStep);
    }
    r->count = static_cast<std::uint32_t>(buffers_.size());
    return 0;
  }
  auto* b = static_cast<v4l2_buffer*>(arg);
  if (request == VIDIOC_QUERYBUF) {
    if (b->index >= buffers_.size()) return fail(EINVAL);
    *b = buffers_[b->index].info;
    return 0;
  }
  if (request == VIDIOC_QBUF) {
    if (b->index >= buffers_.size()) return fail(EINVAL);
    Buffer& x = buffers_[b->index];
    if (x.state == BufState::queued || x.state == BufState::done) return fail(EINVAL);  // queued twice: a bug
    x.state = BufState::queued;
    queued_.push_back(b->index);
    return 0;
  }
  // VIDIOC_DQBUF (non-blocking descriptor)
  if (done_.empty()) return fail(EAGAIN);
  const std::uint32_t i = done_.front();
  done_.pop_front();
  buffers_[i].state = BufState::dequeued;
  *b = buffers_[i].info;
  dequeued_.push_back(i);
  if (done_.empty()) set_ready(false);
  return 0;
}

}  // namespace luxloc::test
