#pragma once
// `--source KIND:TARGET[,key=value...]` (SPEC.md "Source kinds"), parsed once and handed
// to the plugin that owns KIND.
#include <map>
#include <string>
#include <vector>

#include "core/common/sensor_limits.hpp"

namespace luxloc {

struct SourceSpec {
  std::string kind;    // v4l2, serial-imu, uwb, playback, sim
  std::string target;  // /dev/video0, a folder, a scenario name
  std::map<std::string, std::string> params;
  std::string text;    // as written, for messages

  // Throws InputError(field "--source") for a malformed spec.
  static SourceSpec parse(const std::string& text);
  // The value of `key`, or `fallback`; keys not read by the plugin are reported by unused().
  std::string get(const std::string& key, const std::string& fallback) const;
  double get_number(const std::string& key, double fallback) const;  // InputError if not a number
  // The sensor ranges of a live source (`acc_max_g=`, `gyro_max_dps=`, `mag_max_ut=`,
  // `range_max_m=`; each > 0), over `defaults` (core/common/sensor_limits.hpp).
  SensorLimits limits(SensorLimits defaults = {}) const;
  // The keys limits() reads, for the plugins' lists of known keys.
  static const std::vector<std::string>& limit_keys();
};

}  // namespace luxloc
