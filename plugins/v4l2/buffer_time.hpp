#pragma once
// Where a V4L2 buffer's time stamp lies on our live timeline (CLOCK_MONOTONIC ns,
// plugins/serial/monotonic_clock.hpp). Drivers say which clock they stamp with in the
// buffer flags: V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC (all current drivers: used as is);
// V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN (kernels before 3.10 and some out-of-tree drivers stamp
// with gettimeofday, i.e. CLOCK_REALTIME: moved onto the monotonic clock by the offset
// between the two clocks read at dequeue); V4L2_BUF_FLAG_TIMESTAMP_COPY or no stamp at all:
// the frame is stamped on arrival (later than the exposure by the readout and transfer).
// A stamp that is not within kBufferStampWindowNs before the dequeue on the clock it claims
// is not believed either (arrival), so a broken driver clock cannot move frames by hours.
#include <cstdint>

#include "core/common/time.hpp"

namespace luxloc {

enum class BufferClock { monotonic, realtime, arrival };

struct BufferTime {
  TimeNs t = 0;
  BufferClock clock = BufferClock::arrival;
  // The driver's stamp marks the end of the frame (V4L2_BUF_FLAG_TSTAMP_SRC_EOF, the API's
  // default: most non-UVC drivers), not the start of its exposure (TSTAMP_SRC_SOE, which
  // uvcvideo declares). SPEC's frame time is row 0's exposure start, so such a stamp is late
  // by the exposure and the readout of the rows (V4l2Camera moves it back when it knows them).
  bool end_of_frame = false;
};

// 5 s: a frame is dequeued a few frame intervals after its exposure (4 buffers at 1 fps at
// worst), while the two clocks are decades apart (1970 vs boot), so the window cannot mix
// them up; 10 ms ahead of the dequeue allows for the clocks being read one after the other.
inline constexpr TimeNs kBufferStampWindowNs = 5 * kNsPerSecond;
inline constexpr TimeNs kBufferStampAheadNs = 10'000'000;

// flags: v4l2_buffer.flags; stamp_ns: v4l2_buffer.timestamp in ns (0: none); mono_now /
// real_now: CLOCK_MONOTONIC and CLOCK_REALTIME read at the dequeue.
BufferTime buffer_time(std::uint32_t flags, TimeNs stamp_ns, TimeNs mono_now, TimeNs real_now);

}  // namespace luxloc
