#include "plugins/sim/sim_faults.hpp"

#include <cmath>

#include "core/common/input_error.hpp"
#include "core/common/text_split.hpp"

namespace luxloc {
namespace {

double number(const SourceSpec& spec, const std::string& key, const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw InputError("--source", 0, key, "'" + spec.text + "': " + key + ": '" + text + "' is not a number");
}

// "A:B/A:B..." -> pairs; `b_positive`: B must be > 0 (a duration).
std::vector<std::pair<double, double>> pairs(const SourceSpec& spec, const std::string& key, bool b_positive) {
  std::vector<std::pair<double, double>> out;
  const std::string value = spec.get(key, "");
  if (value.empty()) return out;
  for (const std::string& item : split_text(value, '/')) {
    const std::vector<std::string> ab = split_text(item, ':');
    if (ab.size() != 2)
      throw InputError("--source", 0, key,
                       "'" + spec.text + "': " + key + " takes AT:" + (b_positive ? "SECONDS" : "OFFSET") +
                           " (several separated by '/'), got '" + item + "'");
    const double a = number(spec, key, ab[0]), b = number(spec, key, ab[1]);
    if (a < 0 || (b_positive && !(b > 0)))
      throw InputError("--source", 0, key, "'" + spec.text + "': " + key + ": the time must be >= 0" +
                                               (b_positive ? " and the duration > 0" : ""));
    out.emplace_back(a, b);
  }
  return out;
}

bool inside(const std::vector<SimFaults::Window>& ws, double t) {
  for (const auto& w : ws)
    if (t >= w.at_s && t < w.at_s + w.for_s) return true;
  return false;
}

}  // namespace

SimFaults SimFaults::from_spec(const SourceSpec& spec) {
  SimFaults f;
  const std::string die = spec.get("die", "");
  if (!die.empty()) {
    f.die_at_s = number(spec, "die", die);
    if (*f.die_at_s < 0) throw InputError("--source", 0, "die", "'" + spec.text + "': die: the time must be >= 0");
  }
  for (const auto& [a, b] : pairs(spec, "stall", true)) f.stalls.push_back({a, b});
  for (const auto& [a, b] : pairs(spec, "flood", true)) f.floods.push_back({a, b});
  for (const auto& [a, b] : pairs(spec, "jump", false)) f.jumps.push_back({a, b});
  const std::string lag = spec.get("lag", "");
  if (!lag.empty()) {
    f.lag_s = number(spec, "lag", lag);
    if (!(f.lag_s >= 0.0 && f.lag_s <= 2.0))
      throw InputError("--source", 0, "lag", "'" + spec.text + "': lag: the delivery lag must be 0-2 s, got " + lag);
  }
  return f;
}

bool SimFaults::stalled(double t_s) const { return inside(stalls, t_s); }
bool SimFaults::flooding(double t_s) const { return inside(floods, t_s); }

TimeNs SimFaults::clock_error_ns(double t_s) const {
  TimeNs e = 0;
  for (const Jump& j : jumps)
    if (t_s >= j.at_s) e += seconds_to_ns(j.by_s);
  return e;
}

}  // namespace luxloc
