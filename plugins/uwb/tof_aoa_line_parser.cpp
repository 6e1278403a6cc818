#include "plugins/uwb/tof_aoa_line_parser.hpp"

#include <charconv>

#include "plugins/serial/text_fields.hpp"

namespace luxloc {

void TofAoaLineParser::on_line(std::string_view line, TimeNs t, std::vector<SensorData>& out) {
  if (line.front() == '#' || line.rfind("anchor", 0) == 0) return;
  const std::vector<std::string_view> f = split_trimmed(line, ",");
  UwbSample s;
  s.t = t;
  const std::string_view id = f[0];
  const auto [p, ec] = std::from_chars(id.data(), id.data() + id.size(), s.anchor);
  const bool ok = (f.size() == 2 || f.size() == 3) && ec == std::errc() && p == id.data() + id.size() &&
                  parse_finite_number(f[1], s.range_m) && s.range_m >= 0.0 && (f.size() == 2 || parse_finite_number(f[2], s.aoa_rad));
  if (!ok) {
    drops_.add(uwb_drop::kBadLine, "unusable TOF+AOA line: '" + std::string(line.substr(0, 80)) + "'");
    return;
  }
  out.emplace_back(std::in_place_type<UwbSample>, s);
}

}  // namespace luxloc
