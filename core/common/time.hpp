#pragma once
// One internal monotonic timeline: signed 64-bit nanoseconds. Files carry seconds as
// doubles (SPEC.md "Time"); they are converted once, at the edge, with these helpers.
#include <cmath>
#include <cstdint>

namespace luxloc {

using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerSecond = 1'000'000'000;

inline TimeNs seconds_to_ns(double s) { return static_cast<TimeNs>(std::llround(s * 1e9)); }
inline constexpr double ns_to_seconds(TimeNs t) { return static_cast<double>(t) * 1e-9; }

}  // namespace luxloc
