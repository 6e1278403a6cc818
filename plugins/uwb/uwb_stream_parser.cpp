#include "plugins/uwb/uwb_stream_parser.hpp"

#include <charconv>
#include <cmath>

namespace luxloc {

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> f;
  std::size_t i = 0;
  while (true) {
    const std::size_t j = line.find(',', i);
    std::string_view s = line.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    f.push_back(s);
    if (j == std::string_view::npos) break;
    i = j + 1;
  }
  return f;
}

bool parse_number(std::string_view s, double& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size() && std::isfinite(v);
}

void UwbStreamParser::feed(const std::uint8_t* data, std::size_t size, TimeNs t_end, double byte_ns,
                           std::vector<SensorData>& out) {
  for (std::size_t k = 0; k < size; ++k) {
    const char c = static_cast<char>(data[k]);
    if (c == '\n') {
      if (!discarding_) {
        std::string_view l = line_;
        while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t')) l.remove_suffix(1);
        while (!l.empty() && (l.front() == ' ' || l.front() == '\t' || l.front() == '\0' || l.front() == '\r'))
          l.remove_prefix(1);
        if (!l.empty()) {
          ++lines_;
          const TimeNs t = t_end - static_cast<TimeNs>(std::llround(static_cast<double>(size - 1 - k) * byte_ns));
          on_line(l, t, out);
        }
      }
      line_.clear();
      discarding_ = false;
      continue;
    }
    if (discarding_) continue;
    if (line_.size() >= max_line_) {
      drops_.add(uwb_drop::kLongLine, "a line longer than " + std::to_string(max_line_) + " bytes");
      line_.clear();
      discarding_ = true;
      continue;
    }
    line_.push_back(c);
  }
}

}  // namespace luxloc
