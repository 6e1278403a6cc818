#pragma once
// Manual exposure through V4L2 controls (docs/VLC.md "V4L2 camera source", FIELD_NOTES
// "Webcams"). V4L2_CID_EXPOSURE_ABSOLUTE counts in units of 100 us; the kernel names the
// control "exposure_time_absolute" on newer kernels and "exposure_absolute" on older ones
// (the CID is the same), and likewise auto_exposure / exposure_auto and
// exposure_dynamic_framerate / exposure_auto_priority. The CID is what we set; the names
// are matched for messages and for controls found by name.
#include <cstdint>
#include <string>
#include <string_view>

namespace luxloc {

// A V4L2 integer control's range (VIDIOC_QUERYCTRL).
struct ControlRange {
  std::int32_t minimum = 0;
  std::int32_t maximum = 0;
  std::int32_t step = 1;
  std::int32_t default_value = 0;
};

// 100 us per unit of V4L2_CID_EXPOSURE_ABSOLUTE.
inline constexpr double kExposureUnitUs = 100.0;

struct ExposureUnits {
  std::int32_t units = 0;   // value to set
  double applied_us = 0.0;  // what the camera will expose: units x 100 us
  bool adjusted = false;    // rounded or clamped by more than 1 %
  std::string message;      // non-empty when adjusted: what was asked and what is set, and why
};

// Nearest valid control value (range and step) to `exposure_us`; exposure_us must be > 0.
ExposureUnits exposure_us_to_units(double exposure_us, const ControlRange& range);
inline double exposure_units_to_us(std::int32_t units) { return units * kExposureUnitUs; }

// v4l2-ctl's control name for a VIDIOC_QUERYCTRL name: lower case, every run of other
// characters than letters and digits one '_', none at the ends ("Exposure Time, Absolute"
// -> "exposure_time_absolute").
std::string v4l2_control_name(std::string_view queryctrl_name);
// Either kernel's name of the control (by queryctrl or v4l2-ctl name).
bool is_exposure_absolute_name(std::string_view name);
bool is_auto_exposure_name(std::string_view name);
bool is_exposure_dynamic_framerate_name(std::string_view name);

}  // namespace luxloc
