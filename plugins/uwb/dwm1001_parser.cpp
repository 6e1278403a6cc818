#include "plugins/uwb/dwm1001_parser.hpp"

#include <charconv>

#include "plugins/serial/text_fields.hpp"

namespace luxloc {
namespace {

bool parse_hex_id(std::string_view s, int& id) {
  if (s.empty() || s.size() > 4) return false;
  unsigned v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  if (ec != std::errc() || p != s.data() + s.size()) return false;
  id = static_cast<int>(v);
  return true;
}

bool parse_int(std::string_view s, int& v) {
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

std::string excerpt(std::string_view line) {
  std::string s(line.substr(0, 100));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  return s;
}

}  // namespace

bool Dwm1001Parser::parse_pos(const std::vector<std::string_view>& f, std::size_t at, TimeNs t,
                              std::vector<SensorData>& out) {
  // POS,x,y,z,qf
  double x = 0, y = 0, z = 0;
  int q = 0;
  if (f.size() != at + 5 || f[at] != "POS" || !parse_finite_number(f[at + 1], x) || !parse_finite_number(f[at + 2], y) ||
      !parse_finite_number(f[at + 3], z) || !parse_int(f[at + 4], q) || q < 0 || q > 100)
    return false;
  if (options_.emit_position && q >= options_.min_quality) {
    FixSample s;
    s.t = t;
    s.p_inW = {x, y};
    s.sigma_m = options_.position_sigma_m;
    out.push_back(s);
  }
  return true;
}

void Dwm1001Parser::on_line(std::string_view line, TimeNs t, std::vector<SensorData>& out) {
  // Shell chatter is not data: the prompt may also precede a report on the same line.
  if (const std::size_t prompt = line.rfind("dwm>"); prompt != std::string_view::npos) {
    line.remove_prefix(prompt + 4);
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
  }
  if (line.empty()) return;
  const bool dist = line.rfind("DIST,", 0) == 0;
  const bool pos = line.rfind("POS,", 0) == 0;
  if (!dist && !pos) {
    // Command echo, help text, or bytes of a broken report: only the latter is a loss.
    if (line.find("DIST") != std::string_view::npos || line.find("POS,") != std::string_view::npos)
      drops_.add(uwb_drop::kBadLine, "broken DWM1001 line: '" + excerpt(line) + "'");
    return;
  }
  const std::vector<std::string_view> f = split_trimmed(line, ",");
  if (pos) {
    if (!parse_pos(f, 0, t, out)) drops_.add(uwb_drop::kBadPosition, "unusable POS line: '" + excerpt(line) + "'");
    else ++records_;
    return;
  }
  int n = 0;
  if (f.size() < 2 || !parse_int(f[1], n) || n < 0 || n > 64 ||
      (f.size() != 2 + 6 * static_cast<std::size_t>(n) && f.size() != 7 + 6 * static_cast<std::size_t>(n))) {
    drops_.add(uwb_drop::kBadLine, "inconsistent DIST line: '" + excerpt(line) + "'");
    return;
  }
  std::vector<UwbSample> ranges;
  for (int i = 0; i < n; ++i) {
    const std::size_t b = 2 + 6 * static_cast<std::size_t>(i);
    UwbSample s;
    s.t = t;
    double x = 0, y = 0, z = 0;
    if (f[b] != "AN" + std::to_string(i) || !parse_hex_id(f[b + 1], s.anchor) || !parse_finite_number(f[b + 2], x) ||
        !parse_finite_number(f[b + 3], y) || !parse_finite_number(f[b + 4], z) || !parse_finite_number(f[b + 5], s.range_m) ||
        s.range_m < 0.0) {
      drops_.add(uwb_drop::kBadLine, "bad anchor block " + std::to_string(i) + " in '" + excerpt(line) + "'");
      return;
    }
    s.p_AinW = {x, y, z};
    ranges.push_back(s);
  }
  const std::size_t at = 2 + 6 * static_cast<std::size_t>(n);
  ++records_;
  if (options_.emit_ranges)
    for (const UwbSample& s : ranges) out.push_back(s);
  if (f.size() > at && !parse_pos(f, at, t, out))
    drops_.add(uwb_drop::kBadPosition, "unusable POS block in '" + excerpt(line) + "'");
}

}  // namespace luxloc
