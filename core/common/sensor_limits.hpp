#pragma once
// Physical plausibility at the edge (issue 13 part 1): every sensor sample is checked against
// the range its sensor can measure before it is queued, so an impossible value (a 1e30 m/s^2
// accelerometer reading, a gyro rate no MEMS part measures, a negative UWB distance) is
// counted as "out of range" and never reaches the filter. One check for every source kind:
// the playback readers (which name file and line), the serial IMU and UWB sources, the
// simulator and plugin sources.
//
// Per axis, as a sensor's full scale is specified (a 16 g part reads at most 16 g on each
// axis). Defaults: 16 g and 2000 deg/s are the largest full-scale settings of the common
// MEMS IMUs (MPU-6050/9250, BMI160, ICM-20948, WitMotion WT901); a device with a declared
// smaller range (WitMotion acc_range_g=) uses that instead. 1000 uT is 20x the Earth's field
// and beyond the 4900 uT-range parts only next to magnets. UWB: 0-200 m, beyond the
// line-of-sight reach (~100-150 m) of DW1000-class radios; AOA must be finite when present.
#include <optional>
#include <string>

#include "core/common/samples.hpp"

namespace luxloc {

namespace drop_reason {
inline constexpr const char* kOutOfRange = "out of range";  // a value no sensor of its kind measures
}

struct SensorLimits {
  static constexpr double kStandardGravity = 9.80665;
  double acc_max_mps2 = 16.0 * kStandardGravity;    // |a| per axis
  double gyro_max_rad_s = 2000.0 * 3.141592653589793 / 180.0;  // |w| per axis
  double mag_max_ut = 1000.0;                        // |m| per axis
  double range_min_m = 0.0, range_max_m = 200.0;     // UWB distance
  double position_max_m = 1.0e6;                     // |x|, |y| of a fix (1000 km: no building is larger)
  double odom_step_max_m = 100.0;                    // one odometry increment
};

// Why a sample is implausible: the field (a CSV column name) and what is wrong with it.
struct Implausible {
  std::string field;
  std::string what;
};

std::optional<Implausible> check_plausible(const ImuSample& s, const SensorLimits& limits);
std::optional<Implausible> check_plausible(const UwbSample& s, const SensorLimits& limits);
std::optional<Implausible> check_plausible(const FixSample& s, const SensorLimits& limits);
std::optional<Implausible> check_plausible(const OdomSample& s, const SensorLimits& limits);
std::optional<Implausible> check_plausible(const FrameSample& s, const SensorLimits& limits);
std::optional<Implausible> check_plausible(const SensorData& d, const SensorLimits& limits);

// For live sources: true when `d` is plausible; otherwise counts it in `drops` under
// "out of range" with "SOURCE: field 'gx': ..." and returns false.
class DropCounts;
bool admit_plausible(const SensorData& d, const SensorLimits& limits, DropCounts& drops, const std::string& source);

}  // namespace luxloc
