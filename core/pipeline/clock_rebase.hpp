#pragma once
// Detects a live source's clock jumping and re-bases it (issue 13: a source whose clock
// jumps by +/-10 s mid-run must be neither fused as a 10 s gap nor dropped for ever as
// late). A live source's stamps follow the monotonic clock of their arrival (Source::
// clock_follows_arrival): the lag, arrival - stamp, is the source's latency (readout,
// transfer, buffering: milliseconds to tens of ms) and changes slowly. A lag that moves by
// more than kClockJumpNs from its running mean in one sample is a jump of the source's clock
// (a device clock reset, a driver stepping its clock, a wrong stamp base after a
// reconnection): the offset is removed from this sample and every later one, so the stream
// goes on where it was on the timeline, and the jump is counted. Smaller steps are left to
// the merge (reorder window, "late" drops). Used on the source's own pipeline thread.
#include <cstdint>

#include "core/common/time.hpp"

namespace luxloc {

// 1 s: above any latency jitter of a live source (serial and USB buffering, a camera's
// readout, a scheduler hiccup: < 0.1 s), below any clock jump worth re-basing (the merge's
// 60 ms reorder window copes with less).
inline constexpr TimeNs kClockJumpNs = kNsPerSecond;

class ClockRebase {
 public:
  explicit ClockRebase(TimeNs threshold_ns = kClockJumpNs) : threshold_(threshold_ns) {}

  // The corrected stamp of a sample stamped `t` that arrived at `arrival` (ns; the two
  // epochs need not agree, only differences count). jumped() tells whether it re-based.
  TimeNs apply(TimeNs t, TimeNs arrival);
  bool jumped() const { return jumped_; }
  std::uint64_t jumps() const { return jumps_; }
  TimeNs last_jump_ns() const { return last_jump_; }  // > 0: the clock jumped ahead
  TimeNs correction_ns() const { return correction_; }  // added to every stamp now

 private:
  TimeNs threshold_;
  bool have_lag_ = false;
  double mean_lag_ = 0.0;  // running mean of arrival - corrected stamp, ns
  TimeNs correction_ = 0;
  bool jumped_ = false;
  std::uint64_t jumps_ = 0;
  TimeNs last_jump_ = 0;
};

}  // namespace luxloc
