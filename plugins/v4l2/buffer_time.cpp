#include "plugins/v4l2/buffer_time.hpp"

#include <linux/videodev2.h>

namespace luxloc {
namespace {

bool near_before(TimeNs stamp, TimeNs now) {
  return stamp > now - kBufferStampWindowNs && stamp <= now + kBufferStampAheadNs;
}

}  // namespace

BufferTime buffer_time(std::uint32_t flags, TimeNs stamp_ns, TimeNs mono_now, TimeNs real_now) {
  const std::uint32_t clock = flags & V4L2_BUF_FLAG_TIMESTAMP_MASK;
  const bool eof = (flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK) == V4L2_BUF_FLAG_TSTAMP_SRC_EOF;
  if (stamp_ns != 0) {
    if (clock == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC && near_before(stamp_ns, mono_now))
      return {stamp_ns, BufferClock::monotonic, eof};
    if (clock == V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN) {
      if (near_before(stamp_ns, real_now)) return {stamp_ns - (real_now - mono_now), BufferClock::realtime, eof};
      if (near_before(stamp_ns, mono_now)) return {stamp_ns, BufferClock::monotonic, eof};
    }
  }
  return {mono_now, BufferClock::arrival, false};
}

}  // namespace luxloc
