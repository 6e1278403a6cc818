#pragma once
// What a V4L2 device offers, for `luxloc devices`: driver and card, capture formats with
// their frame sizes and intervals, and the controls that matter for VLC (exposure, gain).
#include <cstdint>
#include <string>
#include <vector>

#include "plugins/v4l2/v4l2_camera.hpp"

namespace luxloc {

struct V4l2FrameSize {
  int width = 0, height = 0;
  bool stepwise = false;                // a range: width/height are the maximum, min_* the minimum
  int min_width = 0, min_height = 0;
  std::vector<double> fps;              // discrete frame intervals as rates (empty: not listed)
};

struct V4l2FormatInfo {
  std::uint32_t fourcc = 0;
  std::string description;
  bool emulated = false;  // converted in software by libv4l2
  std::vector<V4l2FrameSize> sizes;
};

struct V4l2DeviceInfo {
  std::string path;
  std::string error;  // non-empty: could not be opened / queried (then only path is valid)
  std::string driver, card, bus;
  bool capture = false;  // a video capture node with streaming I/O
  std::vector<V4l2FormatInfo> formats;
  std::vector<V4l2Control> controls;  // all controls
};

// /dev/video* in numeric order (none: empty).
std::vector<std::string> v4l2_device_paths(const std::string& dev_dir = "/dev");
V4l2DeviceInfo query_v4l2_device(const std::string& path);

}  // namespace luxloc
