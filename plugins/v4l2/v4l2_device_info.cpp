#include "plugins/v4l2/v4l2_device_info.hpp"

#include <fcntl.h>
#include <libv4l2.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace luxloc {
namespace {

std::string cstr(const unsigned char* s, std::size_t n) {
  std::size_t len = 0;
  while (len < n && s[len] != 0) ++len;
  return std::string(reinterpret_cast<const char*>(s), len);
}

int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = v4l2_ioctl(fd, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

std::vector<double> frame_rates(int fd, std::uint32_t fourcc, int w, int h) {
  std::vector<double> out;
  v4l2_frmivalenum fi{};
  fi.pixel_format = fourcc;
  fi.width = static_cast<std::uint32_t>(w);
  fi.height = static_cast<std::uint32_t>(h);
  for (fi.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &fi) == 0; ++fi.index) {
    if (fi.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
      if (fi.discrete.numerator > 0) out.push_back(static_cast<double>(fi.discrete.denominator) / fi.discrete.numerator);
    } else {
      // Continuous / stepwise: the fastest and the slowest rate.
      if (fi.stepwise.min.numerator > 0)
        out.push_back(static_cast<double>(fi.stepwise.min.denominator) / fi.stepwise.min.numerator);
      if (fi.stepwise.max.numerator > 0)
        out.push_back(static_cast<double>(fi.stepwise.max.denominator) / fi.stepwise.max.numerator);
      break;
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> v4l2_device_paths(const std::string& dev_dir) {
  std::vector<std::pair<long, std::string>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dev_dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("video", 0) != 0 || name.size() == 5) continue;
    const std::string num = name.substr(5);
    if (!std::all_of(num.begin(), num.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    found.emplace_back(std::stol(num), e.path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& [n, p] : found) out.push_back(std::move(p));
  return out;
}

V4l2DeviceInfo query_v4l2_device(const std::string& path) {
  V4l2DeviceInfo info;
  info.path = path;
  // Plain open(): the listing shows what the driver offers; v4l2_ioctl on a descriptor
  // libv4l2 did not open passes straight to the kernel.
  const int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    info.error = std::strerror(errno);
    return info;
  }
  v4l2_capability cap{};
  if (xioctl(fd, VIDIOC_QUERYCAP, &cap) != 0) {
    info.error = std::string("not a V4L2 device: ") + std::strerror(errno);
    ::close(fd);
    return info;
  }
  info.driver = cstr(cap.driver, sizeof cap.driver);
  info.card = cstr(cap.card, sizeof cap.card);
  info.bus = cstr(cap.bus_info, sizeof cap.bus_info);
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  info.capture = (caps & V4L2_CAP_VIDEO_CAPTURE) && (caps & V4L2_CAP_STREAMING);
  if (caps & V4L2_CAP_VIDEO_CAPTURE) {
    v4l2_fmtdesc d{};
    d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    for (d.index = 0; xioctl(fd, VIDIOC_ENUM_FMT, &d) == 0; ++d.index) {
      V4l2FormatInfo f;
      f.fourcc = d.pixelformat;
      f.description = cstr(d.description, sizeof d.description);
      f.emulated = (d.flags & V4L2_FMT_FLAG_EMULATED) != 0;
      v4l2_frmsizeenum fs{};
      fs.pixel_format = d.pixelformat;
      for (fs.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &fs) == 0; ++fs.index) {
        V4l2FrameSize s;
        if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
          s.width = static_cast<int>(fs.discrete.width);
          s.height = static_cast<int>(fs.discrete.height);
          s.fps = frame_rates(fd, d.pixelformat, s.width, s.height);
          f.sizes.push_back(std::move(s));
        } else {
          s.stepwise = true;
          s.min_width = static_cast<int>(fs.stepwise.min_width);
          s.min_height = static_cast<int>(fs.stepwise.min_height);
          s.width = static_cast<int>(fs.stepwise.max_width);
          s.height = static_cast<int>(fs.stepwise.max_height);
          f.sizes.push_back(std::move(s));
          break;
        }
      }
      info.formats.push_back(std::move(f));
    }
  }
  info.controls = query_controls(fd);
  ::close(fd);
  return info;
}

}  // namespace luxloc
