#include "plugins/output/pose_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace luxloc {

std::string format_time_s(TimeNs t, int decimals) {
  if (decimals < 0) decimals = 0;
  if (decimals > 9) decimals = 9;
  TimeNs unit = 1;
  for (int i = decimals; i < 9; ++i) unit *= 10;
  const bool negative = t < 0;
  // Magnitude in `unit`s, rounded half away from zero (unsigned: INT64_MIN is safe).
  const std::uint64_t mag = negative ? static_cast<std::uint64_t>(-(t + 1)) + 1 : static_cast<std::uint64_t>(t);
  const std::uint64_t u = static_cast<std::uint64_t>(unit);
  const std::uint64_t q = mag / u + ((mag % u) * 2 >= u ? 1 : 0);
  std::uint64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  char buf[48];
  if (decimals == 0)
    std::snprintf(buf, sizeof buf, "%s%llu", negative && q ? "-" : "", static_cast<unsigned long long>(q));
  else
    std::snprintf(buf, sizeof buf, "%s%llu.%0*llu", negative && q ? "-" : "", static_cast<unsigned long long>(q / scale),
                  decimals, static_cast<unsigned long long>(q % scale));
  return buf;
}

std::string format_fixed(double v, int decimals) {
  if (!std::isfinite(v)) return {};
  // Fixed notation never overflows this buffer: |v| <= 1.8e308 -> at most 309 digits + sign
  // + point + decimals.
  char buf[400];
  const auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, std::clamp(decimals, 0, 17));
  std::string s(buf, res.ptr);
  // "-0.0000" reads as a sign flip in plots and diffs; print it as zero.
  if (s.front() == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

}  // namespace luxloc
