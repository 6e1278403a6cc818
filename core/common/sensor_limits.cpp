#include "core/common/sensor_limits.hpp"

#include <cmath>
#include <sstream>

#include "core/common/drop_counts.hpp"

namespace luxloc {
namespace {

std::string describe(double v, double max, const char* unit) {
  std::ostringstream s;
  s << v << " " << unit;
  if (std::isfinite(v)) s << " beyond the sensor's range of +/-" << max << " " << unit;
  else s << " is not finite";
  return s.str();
}

// The first component of v outside [-max, max] (or not finite), named by `names`.
std::optional<Implausible> check_axes(const Eigen::Vector3d& v, double max, const char* const names[3],
                                      const char* unit) {
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(v[i]) <= max)) return Implausible{names[i], describe(v[i], max, unit)};
  return std::nullopt;
}

}  // namespace

std::optional<Implausible> check_plausible(const ImuSample& s, const SensorLimits& l) {
  static const char* const acc[3] = {"ax", "ay", "az"};
  static const char* const gyro[3] = {"gx", "gy", "gz"};
  static const char* const mag[3] = {"mx", "my", "mz"};
  if (auto r = check_axes(s.acc_inB, l.acc_max_mps2, acc, "m/s^2")) return r;
  if (auto r = check_axes(s.gyro_inB, l.gyro_max_rad_s, gyro, "rad/s")) return r;
  if (s.has_mag)
    if (auto r = check_axes(s.mag_inB, l.mag_max_ut, mag, "uT")) return r;
  return std::nullopt;
}

std::optional<Implausible> check_plausible(const UwbSample& s, const SensorLimits& l) {
  if (!(s.range_m >= l.range_min_m && s.range_m <= l.range_max_m)) {
    std::ostringstream m;
    m << s.range_m << " m outside the radio's range of " << l.range_min_m << "-" << l.range_max_m << " m";
    return Implausible{"range_m", m.str()};
  }
  // NaN is "no angle" (SPEC: aoa_rad optional); an infinite angle is a broken reading.
  if (std::isinf(s.aoa_rad)) return Implausible{"aoa_rad", "not finite"};
  if (!std::isnan(s.aoa_rad) && std::abs(s.aoa_rad) > 1.0e3)
    return Implausible{"aoa_rad", std::to_string(s.aoa_rad) + " rad is not an angle"};
  return std::nullopt;
}

std::optional<Implausible> check_plausible(const FixSample& s, const SensorLimits& l) {
  static const char* const xy[2] = {"x", "y"};
  for (int i = 0; i < 2; ++i)
    if (!(std::abs(s.p_inW[i]) <= l.position_max_m))
      return Implausible{xy[i], describe(s.p_inW[i], l.position_max_m, "m")};
  if (std::isinf(s.sigma_m) || (!std::isnan(s.sigma_m) && s.sigma_m > l.position_max_m))
    return Implausible{"sigma_m", describe(s.sigma_m, l.position_max_m, "m")};
  return std::nullopt;
}

std::optional<Implausible> check_plausible(const OdomSample& s, const SensorLimits& l) {
  if (!(std::abs(s.dist_m) <= l.odom_step_max_m)) return Implausible{"dist_m", describe(s.dist_m, l.odom_step_max_m, "m")};
  // One increment of more than 100 turns is a broken reading, whatever the rate.
  if (!(std::abs(s.dyaw_rad) <= 200.0 * 3.141592653589793))
    return Implausible{"dyaw_rad", describe(s.dyaw_rad, 200.0 * 3.141592653589793, "rad")};
  return std::nullopt;
}

std::optional<Implausible> check_plausible(const FrameSample&, const SensorLimits&) { return std::nullopt; }

std::optional<Implausible> check_plausible(const SensorData& d, const SensorLimits& l) {
  return std::visit([&](const auto& s) { return check_plausible(s, l); }, d);
}

bool admit_plausible(const SensorData& d, const SensorLimits& limits, DropCounts& drops, const std::string& source) {
  const auto bad = check_plausible(d, limits);
  if (!bad) return true;
  drops.add(drop_reason::kOutOfRange, source + ": field '" + bad->field + "': " + bad->what);
  return false;
}

}  // namespace luxloc
