#include "plugins/source_spec.hpp"

#include <charconv>
#include <cmath>

#include "core/common/input_error.hpp"

namespace luxloc {

SourceSpec SourceSpec::parse(const std::string& text) {
  SourceSpec s;
  s.text = text;
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon == 0)
    throw InputError("--source", 0, "--source", "'" + text + "': expected KIND:TARGET[,key=value...]");
  s.kind = text.substr(0, colon);
  std::string rest = text.substr(colon + 1);
  // TARGET runs to the first comma that starts a key=value pair.
  std::size_t pos = rest.find(',');
  s.target = rest.substr(0, pos);
  while (pos != std::string::npos) {
    const std::size_t next = rest.find(',', pos + 1);
    const std::string kv = rest.substr(pos + 1, next == std::string::npos ? std::string::npos : next - pos - 1);
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--source", 0, "--source", "'" + text + "': '" + kv + "' is not key=value");
    s.params[kv.substr(0, eq)] = kv.substr(eq + 1);
    pos = next;
  }
  if (s.target.empty()) throw InputError("--source", 0, "--source", "'" + text + "': empty TARGET");
  return s;
}

std::string SourceSpec::get(const std::string& key, const std::string& fallback) const {
  auto it = params.find(key);
  return it == params.end() ? fallback : it->second;
}

double SourceSpec::get_number(const std::string& key, double fallback) const {
  auto it = params.find(key);
  if (it == params.end()) return fallback;
  double v = 0;
  const auto& str = it->second;
  const auto [p, ec] = std::from_chars(str.data(), str.data() + str.size(), v);
  if (ec != std::errc() || p != str.data() + str.size() || !std::isfinite(v))
    throw InputError("--source", 0, key, "'" + text + "': '" + str + "' is not a number");
  return v;
}

SensorLimits SourceSpec::limits(SensorLimits l) const {
  const auto positive = [&](const char* key, double scale, double& out) {
    if (!params.count(key)) return;
    const double v = get_number(key, 0.0);
    if (!(v > 0.0)) throw InputError("--source", 0, key, "'" + text + "': must be > 0");
    out = v * scale;
  };
  positive("acc_max_g", SensorLimits::kStandardGravity, l.acc_max_mps2);
  positive("gyro_max_dps", 3.141592653589793 / 180.0, l.gyro_max_rad_s);
  positive("mag_max_ut", 1.0, l.mag_max_ut);
  positive("range_max_m", 1.0, l.range_max_m);
  return l;
}

const std::vector<std::string>& SourceSpec::limit_keys() {
  static const std::vector<std::string> keys = {"acc_max_g", "gyro_max_dps", "mag_max_ut", "range_max_m"};
  return keys;
}

}  // namespace luxloc
