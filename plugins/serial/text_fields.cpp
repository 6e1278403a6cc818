#include "plugins/serial/text_fields.hpp"

#include <charconv>
#include <cmath>

namespace luxloc {

std::vector<std::string_view> split_trimmed(std::string_view line, std::string_view delimiters) {
  std::vector<std::string_view> f;
  std::size_t i = 0;
  while (true) {
    const std::size_t j = line.find_first_of(delimiters, i);
    std::string_view s = line.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    f.push_back(s);
    if (j == std::string_view::npos) break;
    i = j + 1;
  }
  return f;
}

bool parse_finite_number(std::string_view s, double& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size() && std::isfinite(v);
}

}  // namespace luxloc
