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
    // 100 km: far beyond any building (a site is kilometres at most), and small enough that
    // the spatial index's cell arithmetic stays exact (fuzz_session: x = 1.7e31 overflowed it).
    if (!(l.p_inW.cwiseAbs().maxCoeff() <= kMaxCoordinateM))
      throw InputError(origin, 0, "x/y/z", label + ": position beyond " + std::to_string(int(kMaxCoordinateM / 1000)) +
                                               " km of the origin (map in metres?)");
    if (!(l.duty > 0.0 && l.duty < 1.0)) throw InputError(origin, 0, "duty", label + ": must be in (0, 1)");
    if (!(l.half_power_angle_deg > 0.0 && l.half_power_angle_deg < 90.0))
      throw InputError(origin, 0, "half_power_angle_deg", label + ": must be in (0, 90)");
    if (!(l.power > 0.0)) throw InputError(origin, 0, "power", label + ": must be > 0");
  }
  build_classes(origin, options);
}

void LedMap::build_classes(const std::string& origin, const LedMapOptions& options) {
  // Sorted by frequency, neighbours either are copies (within same_class_tolerance of the
  // class's first member) or are separable (min_relative_separation); anything between is
  // a map the decoder would misread. O(n log n), for maps of thousands of LEDs.
  std::vector<int> order(leds_.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return leds_[a].freq_hz < leds_[b].freq_hz; });
  class_of_.assign(leds_.size(), -1);
  classes_.clear();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const Led& l = leds_[static_cast<std::size_t>(order[k])];
    if (!classes_.empty()) {
      const FrequencyClass& last = classes_.back();
      const Led& first = leds_[static_cast<std::size_t>(last.members.front())];
      const double rel = (l.freq_hz - first.freq_hz) / first.freq_hz;
      if (rel <= options.same_class_tolerance) {
        classes_.back().members.push_back(order[k]);
        continue;
      }
      const Led& prev = leds_[static_cast<std::size_t>(order[k - 1])];
      const double gap = (l.freq_hz - prev.freq_hz) / prev.freq_hz;
      if (gap < options.min_relative_separation) {
        std::ostringstream s;
        s << "LED id " << l.id << " (" << l.freq_hz << " Hz) and LED id " << prev.id << " (" << prev.freq_hz
          << " Hz) differ by " << gap * 100 << " %, closer than the decoder can tell apart (needs >= "
          << options.min_relative_separation * 100 << " %; copies of one frequency must agree within "
          << options.same_class_tolerance * 100 << " %)";
        throw InputError(origin, 0, "freq_hz", s.str());
      }
    }
    classes_.push_back({});
    classes_.back().members.push_back(order[k]);
  }
  min_reuse_distance_m_ = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < classes_.size(); ++c) {
    FrequencyClass& fc = classes_[c];
    double f = 0.0, z = 0.0;
    for (int i : fc.members) {
      class_of_[static_cast<std::size_t>(i)] = static_cast<int>(c);
      f += leds_[static_cast<std::size_t>(i)].freq_hz;
      z += leds_[static_cast<std::size_t>(i)].p_inW.z();
    }
    fc.freq_hz = f / static_cast<double>(fc.members.size());
    fc.mean_z = z / static_cast<double>(fc.members.size());
    // Pairwise within a class: classes are small (a reused frequency has tens of copies).
    for (std::size_t a = 0; a < fc.members.size(); ++a)
      for (std::size_t b = a + 1; b < fc.members.size(); ++b)
        min_reuse_distance_m_ = std::min(min_reuse_distance_m_,
                                         (leds_[static_cast<std::size_t>(fc.members[a])].p_inW.head<2>() -
                                          leds_[static_cast<std::size_t>(fc.members[b])].p_inW.head<2>())
                                             .norm());
  }
  if (!leds_.empty()) {
    bounds_ << leds_[0].p_inW.x(), leds_[0].p_inW.y(), leds_[0].p_inW.x(), leds_[0].p_inW.y();
    for (const Led& l : leds_) {
      bounds_[0] = std::min(bounds_[0], l.p_inW.x());
      bounds_[1] = std::min(bounds_[1], l.p_inW.y());
      bounds_[2] = std::max(bounds_[2], l.p_inW.x());
      bounds_[3] = std::max(bounds_[3], l.p_inW.y());
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
    l.diameter_known = !f.member(n, "diameter_m", label).empty();
    l.diameter_m = read_number(f, n, label, "diameter_m", false, 0.15);
    if (l.diameter_known && !(l.diameter_m > 0.0 && l.diameter_m < 5.0))
      f.fail("diameter_m", label, "must be > 0 and < 5 m (the LED's diameter)");
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
       << "power" << l.power;
    if (l.diameter_known) fs << "diameter_m" << l.diameter_m;  // a placeholder is not written as if measured
    fs << "}";
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
  // Binary search in the sorted class frequencies: the best and runner-up are the two
  // neighbours of f (or one of them and the next one out).
  const auto it = std::lower_bound(classes_.begin(), classes_.end(), f_hz,
                                   [](const FrequencyClass& c, double f) { return c.freq_hz < f; });
  const auto first = static_cast<std::ptrdiff_t>(it - classes_.begin());
  int best = -1;
  for (std::ptrdiff_t k = std::max<std::ptrdiff_t>(0, first - 2);
       k < std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(classes_.size()), first + 2); ++k) {
    const double e = std::abs(f_hz - classes_[static_cast<std::size_t>(k)].freq_hz) / classes_[static_cast<std::size_t>(k)].freq_hz;
    if (e < m.rel_error) {
      m.runner_up = m.rel_error;
      m.rel_error = e;
      best = static_cast<int>(k);
    } else if (e < m.runner_up) {
      m.runner_up = e;
    }
  }
  if (best >= 0 && m.rel_error <= rel_tolerance) {
    m.klass = best;
    const FrequencyClass& c = classes_[static_cast<std::size_t>(best)];
    m.index = c.members.size() == 1 ? c.members.front() : -1;
  }
  return m;
}

double LedMap::min_relative_separation() const {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < classes_.size(); ++k)
    best = std::min(best, (classes_[k].freq_hz - classes_[k - 1].freq_hz) / classes_[k - 1].freq_hz);
  return best;
}

}  // namespace luxloc
