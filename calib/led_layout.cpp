#include "calib/led_layout.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <string_view>
#include <unordered_map>

#include "core/common/csv_reader.hpp"
#include "core/common/input_error.hpp"
#include "core/common/yaml_reader.hpp"

namespace luxloc {
namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    const char c = s[s.size() - suffix.size() + i];
    if (static_cast<char>(std::tolower(static_cast<unsigned char>(c))) != suffix[i]) return false;
  }
  return true;
}

bool parses_as_number(std::string_view s) {
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
}

void check_coordinates(const Led& l, const std::string& file, int line, const std::string& where) {
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(l.p_inW[k]) <= kMaxLayoutCoordinate))
      throw InputError(file, line, std::string(1, "xyz"[k]),
                       where + (where.empty() ? "" : ": ") + "beyond +-" + std::to_string(static_cast<long>(kMaxLayoutCoordinate)) +
                           " m (a coordinate in metres is expected)");
}

void finish(LedLayout& layout) {
  if (layout.leds.empty()) throw InputError(layout.origin, 0, "", "the layout holds no LED");
  layout.max_z = layout.leds.front().p_inW.z();
  for (const Led& l : layout.leds) layout.max_z = std::max(layout.max_z, l.p_inW.z());
}

}  // namespace

LedLayout read_led_layout(const std::string& path, std::optional<double> ceiling_z) {
  if (ends_with(path, ".csv")) return read_led_layout_csv(path, ceiling_z);
  if (ends_with(path, ".yaml") || ends_with(path, ".yml")) return read_led_layout_yaml(path, ceiling_z);
  throw InputError(path, 0, "--layout",
                   "unknown layout format: give a .csv (x,y[,z][,id]) or a .yaml LED map, or use --grid");
}

LedLayout read_led_layout_csv(const std::string& path, std::optional<double> ceiling_z) {
  CsvReader r(path);
  LedLayout layout;
  layout.origin = path;
  const int header_line = r.line();
  if (!r.header().empty() && parses_as_number(r.header().front()))
    throw InputError(path, header_line, "x",
                     "no header row: the first line must name the columns (x,y or x,y,z, optional id), found '" +
                         r.header().front() + "'");
  const int cx = r.require_column("x"), cy = r.require_column("y");
  const int cz = r.column("z"), cid = r.column("id");
  layout.ids_given = cid >= 0;
  std::set<int> ids;
  while (r.next_row()) {
    if (layout.leds.size() >= kMaxLayoutLeds)
      throw InputError(path, r.line(), "", "more than " + std::to_string(kMaxLayoutLeds) + " LEDs");
    Led l;
    l.p_inW.x() = r.number(cx);
    l.p_inW.y() = r.number(cy);
    const double z = r.number_or(cz, std::nan(""));
    if (std::isfinite(z)) {
      l.p_inW.z() = z;
    } else if (ceiling_z) {
      l.p_inW.z() = *ceiling_z;
    } else {
      throw InputError(path, r.line(), "z",
                       cz < 0 ? "the layout has no z column: give --ceiling-height" : "empty z: give --ceiling-height");
    }
    if (cid >= 0) {
      const long long id = r.integer(cid);
      if (id < 0 || id > 2147483647LL) throw InputError(path, r.line(), "id", "must be 0 .. 2147483647");
      l.id = static_cast<int>(id);
      if (!ids.insert(l.id).second) throw InputError(path, r.line(), "id", "duplicate id " + std::to_string(l.id));
    } else {
      l.id = static_cast<int>(layout.leds.size()) + 1;
    }
    l.freq_hz = 0.0;
    check_coordinates(l, path, r.line(), "");
    layout.leds.push_back(l);
  }
  finish(layout);
  return layout;
}

LedLayout read_led_layout_yaml(const std::string& path, std::optional<double> ceiling_z) {
  const YamlFile f(path, "LED map");
  const cv::FileNode seq = f["leds"];
  if (yaml_absent(seq)) f.fail("leds", "", "missing (expected a sequence of {id, x, y[, z]})");
  f.expect_seq(seq, "leds", "");
  LedLayout layout;
  layout.origin = path;
  layout.ids_given = true;
  std::set<int> ids;
  std::size_t index = 0;
  const auto number = [&](const cv::FileNode& n, const char* key, const std::string& where, double fallback,
                          bool required) {
    const cv::FileNode v = f.member(n, key, where);
    if (yaml_absent(v)) {
      if (required) f.fail(key, where, "missing required field");
      return fallback;
    }
    return f.number(v, key, where);
  };
  for (auto it = seq.begin(); it != seq.end(); ++it, ++index) {
    const cv::FileNode n = *it;
    const std::string number_label = "LED #" + std::to_string(index + 1);
    if (!n.isMap()) f.fail("leds", number_label, "not a mapping {id, x, y, z}");
    if (layout.leds.size() >= kMaxLayoutLeds)
      f.fail("leds", number_label, "more than " + std::to_string(kMaxLayoutLeds) + " LEDs");
    Led l;
    const cv::FileNode idn = f.member(n, "id", number_label);
    if (yaml_absent(idn)) f.fail("id", number_label, "missing required field");
    l.id = f.integer(idn, "id", number_label);
    const std::string label = number_label + " (id " + std::to_string(l.id) + ")";
    if (!ids.insert(l.id).second) f.fail("id", label, "duplicate id");
    l.p_inW.x() = number(n, "x", label, 0.0, true);
    l.p_inW.y() = number(n, "y", label, 0.0, true);
    const double z = number(n, "z", label, std::nan(""), false);
    if (std::isfinite(z))
      l.p_inW.z() = z;
    else if (ceiling_z)
      l.p_inW.z() = *ceiling_z;
    else
      f.fail("z", label, "missing (give it, or --ceiling-height)");
    // Kept from the map: what the light is (the plan changes only its frequency).
    l.duty = number(n, "duty", label, l.duty, false);
    l.half_power_angle_deg = number(n, "half_power_angle_deg", label, l.half_power_angle_deg, false);
    l.power = number(n, "power", label, l.power, false);
    l.freq_hz = 0.0;  // ignored: the plan assigns it
    check_coordinates(l, path, 0, label);
    layout.leds.push_back(l);
  }
  finish(layout);
  return layout;
}

LedLayout grid_led_layout(const std::string& spec, std::optional<double> ceiling_z) {
  const std::string origin = "--grid";
  const auto bad = [&](const std::string& what) -> InputError {
    return InputError(origin, 0, "--grid", "'" + spec + "': " + what + " (expected X0:X1:DX,Y0:Y1:DY in metres)");
  };
  const std::size_t comma = spec.find(',');
  if (comma == std::string::npos || spec.find(',', comma + 1) != std::string::npos)
    throw bad("two ranges separated by one comma");
  struct Range {
    double lo, hi, step;
    std::size_t count;
  };
  const auto range = [&](std::string_view s, const char* axis) {
    double v[3];
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
      const std::size_t colon = s.find(':', start);
      if ((i < 2) != (colon != std::string_view::npos)) throw bad(std::string(axis) + " range needs three numbers A:B:STEP");
      const std::string_view part = s.substr(start, i < 2 ? colon - start : std::string_view::npos);
      if (!parses_as_number(part)) throw bad(std::string(axis) + ": not a number: '" + std::string(part) + "'");
      std::from_chars(part.data(), part.data() + part.size(), v[i]);
      if (!std::isfinite(v[i])) throw bad(std::string(axis) + ": not finite");
      start = colon + 1;
    }
    if (!(v[2] > 0.0)) throw bad(std::string(axis) + ": the step must be > 0");
    if (v[1] < v[0]) throw bad(std::string(axis) + ": the end is below the start");
    if (std::abs(v[0]) > kMaxLayoutCoordinate || std::abs(v[1]) > kMaxLayoutCoordinate)
      throw bad(std::string(axis) + ": beyond +-" + std::to_string(static_cast<long>(kMaxLayoutCoordinate)) + " m");
    const double steps = std::floor((v[1] - v[0]) / v[2] + 1e-9);
    if (steps + 1.0 > static_cast<double>(kMaxLayoutLeds)) throw bad(std::string(axis) + ": too many lights");
    return Range{v[0], v[1], v[2], static_cast<std::size_t>(steps) + 1};
  };
  const Range rx = range(std::string_view(spec).substr(0, comma), "x");
  const Range ry = range(std::string_view(spec).substr(comma + 1), "y");
  if (static_cast<double>(rx.count) * static_cast<double>(ry.count) > static_cast<double>(kMaxLayoutLeds))
    throw bad(std::to_string(rx.count) + " x " + std::to_string(ry.count) + " lights, more than " +
              std::to_string(kMaxLayoutLeds));
  if (!ceiling_z) throw InputError(origin, 0, "--ceiling-height", "a grid needs --ceiling-height (the LEDs' z)");
  LedLayout layout;
  layout.origin = origin;
  layout.leds.reserve(rx.count * ry.count);
  for (std::size_t j = 0; j < ry.count; ++j)
    for (std::size_t i = 0; i < rx.count; ++i) {
      Led l;
      l.id = static_cast<int>(layout.leds.size()) + 1;
      l.p_inW = {rx.lo + rx.step * static_cast<double>(i), ry.lo + ry.step * static_cast<double>(j), *ceiling_z};
      l.freq_hz = 0.0;
      layout.leds.push_back(l);
    }
  finish(layout);
  return layout;
}

LayoutDensity densest_cluster(const LedLayout& layout, double conflict_distance_m) {
  LayoutDensity out;
  const double r = 0.5 * conflict_distance_m;
  if (layout.leds.empty() || !(r > 0.0)) return out;
  // Sparse cells (hashed by the cell index, compared exactly): the extent does not matter.
  // Coordinates are within kMaxLayoutCoordinate (checked by the readers), r >= 1e-6 here.
  using Cell = std::pair<std::int64_t, std::int64_t>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      return std::hash<std::uint64_t>{}(static_cast<std::uint64_t>(c.first) * 0x9E3779B97F4A7C15ULL ^
                                        static_cast<std::uint64_t>(c.second));
    }
  };
  const double rr = std::max(r, 1e-6);
  const auto key = [rr](double x, double y) {
    return Cell{static_cast<std::int64_t>(std::floor(x / rr)), static_cast<std::int64_t>(std::floor(y / rr))};
  };
  std::unordered_map<Cell, std::vector<int>, CellHash> cells;
  for (std::size_t i = 0; i < layout.leds.size(); ++i)
    cells[key(layout.leds[i].p_inW.x(), layout.leds[i].p_inW.y())].push_back(static_cast<int>(i));
  for (std::size_t i = 0; i < layout.leds.size(); ++i) {
    const Eigen::Vector2d p = layout.leds[i].p_inW.head<2>();
    const auto [cx, cy] = key(p.x(), p.y());
    int count = 0;
    for (std::int64_t y = cy - 1; y <= cy + 1; ++y)
      for (std::int64_t x = cx - 1; x <= cx + 1; ++x) {
        const auto it = cells.find(Cell{x, y});
        if (it == cells.end()) continue;
        for (int j : it->second) {
          const Eigen::Vector2d q = layout.leds[static_cast<std::size_t>(j)].p_inW.head<2>();
          if ((q - p).norm() < r) ++count;
        }
      }
    if (count > out.leds_within) {
      out.leds_within = count;
      out.centre = static_cast<int>(i);
    }
  }
  return out;
}

}  // namespace luxloc
