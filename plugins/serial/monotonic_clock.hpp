#pragma once
// Arrival timestamps of live serial data: CLOCK_MONOTONIC in nanoseconds, taken as is as
// TimeNs. The monotonic clock never jumps (NTP or the user setting the date cannot move it)
// and is the clock of V4L2 buffer timestamps (V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC), so live
// sources that use it share one timeline. Its epoch is the boot: meaningless across
// machines and reboots, fine within a run.
#include <ctime>

#include "core/common/time.hpp"

namespace luxloc {

inline TimeNs monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * kNsPerSecond + ts.tv_nsec;
}

}  // namespace luxloc
