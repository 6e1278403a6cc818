#include "plugins/v4l2/exposure_control.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace luxloc {

ExposureUnits exposure_us_to_units(double exposure_us, const ControlRange& range) {
  ExposureUnits e;
  const double wanted = exposure_us / kExposureUnitUs;
  const std::int32_t lo = std::min(range.minimum, range.maximum), hi = std::max(range.minimum, range.maximum);
  const std::int32_t step = std::max<std::int32_t>(range.step, 1);
  double v = std::clamp(wanted, static_cast<double>(lo), static_cast<double>(hi));
  // Snap to the step grid that starts at the minimum, staying inside the range.
  double k = std::round((v - lo) / step);
  const double k_max = std::floor(static_cast<double>(hi - lo) / step);
  k = std::clamp(k, 0.0, k_max);
  e.units = static_cast<std::int32_t>(lo + k * step);
  e.applied_us = exposure_units_to_us(e.units);
  e.adjusted = std::abs(e.applied_us - exposure_us) > 0.01 * exposure_us;
  if (e.adjusted) {
    char buf[256];
    const char* why = wanted < lo   ? "below the camera's minimum"
                      : wanted > hi ? "above the camera's maximum"
                                    : "not a multiple of the control's step";
    std::snprintf(buf, sizeof buf, "exposure %.0f us is %s (%d..%d x 100 us, step %d): set to %d x 100 us = %.0f us",
                  exposure_us, why, lo, hi, step, e.units, e.applied_us);
    e.message = buf;
  }
  return e;
}

std::string v4l2_control_name(std::string_view queryctrl_name) {
  std::string out;
  bool pending = false;
  for (const char ch : queryctrl_name) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c)) {
      if (pending && !out.empty()) out.push_back('_');
      pending = false;
      out.push_back(static_cast<char>(std::tolower(c)));
    } else {
      pending = true;
    }
  }
  return out;
}

namespace {
bool name_is(std::string_view name, std::string_view a, std::string_view b) {
  const std::string n = v4l2_control_name(name);
  return n == a || n == b;
}
}  // namespace

bool is_exposure_absolute_name(std::string_view name) {
  return name_is(name, "exposure_time_absolute", "exposure_absolute");
}
bool is_auto_exposure_name(std::string_view name) { return name_is(name, "auto_exposure", "exposure_auto"); }
bool is_exposure_dynamic_framerate_name(std::string_view name) {
  return name_is(name, "exposure_dynamic_framerate", "exposure_auto_priority");
}

}  // namespace luxloc
