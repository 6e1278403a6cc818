#include "core/vlc/led_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <set>
#include <sstream>

#include "core/common/input_error.hpp"
#include "core/common/yaml_reader.hpp"

namespace luxloc {
namespace {

std::string led_label(std::size_t index, int id) {
  return "LED #" + std::to_string(index + 1) + " (id " + std::to_string(id) + ")";
}

double read_number(const YamlFile& f, const cv::FileNode& led, const std::string& label, const char* field,
                   bool required, double fallback) {
  const cv::FileNode n = f.member(led, field, label);
  if (n.empty()) {
    if (required) f.fail(field, label, "missing required field");
    return fallback;
  }
  return f.number(n, field, label);
}

}  // namespace

LedMap::LedMap(std::vector<Led> leds, std::string origin, const LedMapOptions& options)
    : leds_(std::move(leds)) {
  std::set<int> ids;
  for (std::size_t i = 0; i < leds_.size(); ++i) {
    const Led& l = leds_[i];
    const std::string label = "LED #" + std::to_string(i + 1) + " (id " + std::to_string(l.id) + ")";
    if (!ids.insert(l.id).second) throw InputError(origin, 0, "id", label + ": duplicate id");
    if (!(l.freq_hz > 0.0) || !std::isfinite(l.freq_hz))
      throw InputError(origin, 0, "freq_hz", label + ": must be > 0");
    if (!l.p_inW.allFinite()) throw InputError(origin, 0, "x/y/z", label + ": position not finite");
    if (!(l.duty > 0.0 && l.duty < 1.0)) throw InputError(origin, 0, "duty", label + ": must be in (0, 1)");
    if (!(l.half_power_angle_deg > 0.0 && l.half_power_angle_deg < 90.0))
      throw InputError(origin, 0, "half_power_angle_deg", label + ": must be in (0, 90)");
    if (!(l.power > 0.0)) throw InputError(origin, 0, "power", label + ": must be > 0");
  }
  for (std::size_t i = 0; i < leds_.size(); ++i)
    for (std::size_t j = i + 1; j < leds_.size(); ++j) {
      const double a = leds_[i].freq_hz, b = leds_[j].freq_hz;
      const double rel = std::abs(a - b) / std::min(a, b);
      if (rel < options.min_relative_separation) {
        std::ostringstream s;
        s << "LED id " << leds_[j].id << " (" << b << " Hz) and LED id " << leds_[i].id << " (" << a
          << " Hz) differ by " << rel * 100 << " %, closer than the decoder can tell apart (needs >= "
          << options.min_relative_separation * 100 << " %)";
        throw InputError(origin, 0, "freq_hz", s.str());
      }
    }
}

LedMap LedMap::load(const std::string& path, const LedMapOptions& options) {
  const YamlFile f(path, "LED map");
  const cv::FileNode seq = f["leds"];
  if (seq.empty()) f.fail("leds", "", "missing (expected a sequence of {id, freq_hz, x, y, z})");
  f.expect_seq(seq, "leds", "");
  std::vector<Led> leds;
  std::size_t index = 0;
  for (auto it = seq.begin(); it != seq.end(); ++it, ++index) {
    const cv::FileNode n = *it;
    const std::string number = "LED #" + std::to_string(index + 1);
    if (!n.isMap()) f.fail("leds", number, "not a mapping {id, freq_hz, x, y, z}");
    Led l;
    const cv::FileNode idn = f.member(n, "id", number);
    if (idn.empty()) f.fail("id", number, "missing required field");
    l.id = f.integer(idn, "id", number);
    const std::string label = led_label(index, l.id);
    l.freq_hz = read_number(f, n, label, "freq_hz", true, 0);
    l.p_inW.x() = read_number(f, n, label, "x", true, 0);
    l.p_inW.y() = read_number(f, n, label, "y", true, 0);
    l.p_inW.z() = read_number(f, n, label, "z", true, 0);
    l.duty = read_number(f, n, label, "duty", false, 0.5);
    l.half_power_angle_deg = read_number(f, n, label, "half_power_angle_deg", false, 60.0);
    l.power = read_number(f, n, label, "power", false, 1.0);
    l.diameter_m = read_number(f, n, label, "diameter_m", false, 0.15);
    leds.push_back(l);
  }
  if (leds.empty()) f.fail("leds", "", "the map holds no LED");
  return LedMap(std::move(leds), path, options);
}

void LedMap::save(const std::string& path) const {
  cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  if (!fs.isOpened()) throw InputError(path, 0, "", "cannot write LED map");
  fs << "leds" << "[";
  for (const Led& l : leds_) {
    fs << "{:" << "id" << l.id << "freq_hz" << l.freq_hz << "x" << l.p_inW.x() << "y" << l.p_inW.y()
       << "z" << l.p_inW.z() << "duty" << l.duty << "half_power_angle_deg" << l.half_power_angle_deg
       << "power" << l.power << "diameter_m" << l.diameter_m << "}";
  }
  fs << "]";
}

const Led* LedMap::find_id(int id) const {
  for (const Led& l : leds_)
    if (l.id == id) return &l;
  return nullptr;
}

LedMap::FrequencyMatch LedMap::match_frequency(double f_hz, double rel_tolerance) const {
  FrequencyMatch m;
  int best = -1;
  for (std::size_t i = 0; i < leds_.size(); ++i) {
    const double e = std::abs(f_hz - leds_[i].freq_hz) / leds_[i].freq_hz;
    if (e < m.rel_error) {
      m.runner_up = m.rel_error;
      m.rel_error = e;
      best = static_cast<int>(i);
    } else if (e < m.runner_up) {
      m.runner_up = e;
    }
  }
  m.index = (best >= 0 && m.rel_error <= rel_tolerance) ? best : -1;
  return m;
}

double LedMap::min_relative_separation() const {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < leds_.size(); ++i)
    for (std::size_t j = i + 1; j < leds_.size(); ++j) {
      const double a = leds_[i].freq_hz, b = leds_[j].freq_hz;
      best = std::min(best, std::abs(a - b) / std::min(a, b));
    }
  return best;
}

}  // namespace luxloc
