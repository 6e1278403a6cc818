#pragma once
// How late a live source's samples arrive after their own time stamps (its latency: a
// camera's readout, USB transfer and driver buffering, 30-150 ms for webcams; serial
// buffering for an IMU), so that the merger waits for a lagging source instead of dropping
// all its samples as late. A camera stamped at the start of its exposure (SPEC: row 0) is
// handed over a frame time or more after that stamp; with a fixed 60 ms reorder window a
// 15 fps webcam lost every frame. Runs on the fusion thread; fed with every sample taken
// from the source's queue, fused or dropped (a late sample teaches the lag too).
//
// high(): a level that a new sample's lag rarely exceeds: it jumps up to any larger lag and
// relaxes towards the current lag with a time constant of kLagRelaxS, so a scheduler hiccup
// lengthens the merger's waits for a few seconds, not for the rest of the run.
#include <cstdint>

#include "core/common/time.hpp"

namespace luxloc {

// 5 s: a few seconds of frames (75-150 at 15-30 fps) in which a lag spike still counts;
// a camera's lag changes with its mode, not from one second to the next.
inline constexpr double kLagRelaxS = 5.0;

class SourceLag {
 public:
  // A sample stamped `stamp` (ns, the source's clock after offsets and re-basing) taken
  // from the queue, where it had arrived at `arrival` (ns, the monotonic arrival clock).
  void update(TimeNs stamp, TimeNs arrival);
  bool known() const { return n_ > 0; }
  std::uint64_t count() const { return n_; }
  TimeNs high_ns() const { return static_cast<TimeNs>(high_); }
  double mean_s() const { return n_ ? 1e-9 * sum_ / static_cast<double>(n_) : 0.0; }
  double max_s() const { return 1e-9 * max_; }

 private:
  std::uint64_t n_ = 0;
  double high_ = 0.0, sum_ = 0.0, max_ = 0.0;  // ns
  TimeNs last_stamp_ = 0;
};

}  // namespace luxloc
