#pragma once
// Faults injected into the `sim:` live source, for tests and demos of the live path's
// fault handling (docs/RELIABILITY.md "Faults of live sources"). Source options, times in
// seconds of simulated time from the start of the run, several of one kind separated by '/':
//   die=T          the source ends at T with a failure (like a device that is unplugged)
//   stall=T:D      no sample from T to T+D (a device that stops sending, then resumes;
//                  the samples of the gap are lost, as a real device's would be)
//   flood=T:D      from T to T+D every sample is sent 10 times (copies spread over the
//                  interval to the stream's next sample: 10x the rate)
//   jump=T:S       from T on every time stamp is S seconds off (S may be negative; jumps
//                  add up), while the samples are still sent at the true time
//   lag=S          every sample is handed over S seconds (0-2) after its time stamp: a
//                  webcam's readout, USB transfer and driver buffering (30-150 ms), while
//                  its stamp stays the exposure's start
// e.g. `--source sim:walk,streams=frames,stall=5:5,jump=10:+10`.
#include <optional>
#include <string>
#include <vector>

#include "core/common/time.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc {

inline constexpr int kSimFloodFactor = 10;

struct SimFaults {
  struct Window {
    double at_s = 0.0, for_s = 0.0;
  };
  struct Jump {
    double at_s = 0.0, by_s = 0.0;
  };
  std::optional<double> die_at_s;
  std::vector<Window> stalls, floods;
  std::vector<Jump> jumps;
  double lag_s = 0.0;

  // From the spec's die / stall / flood / jump / lag keys; throws InputError (field = the key).
  static SimFaults from_spec(const SourceSpec& spec);
  bool empty() const { return !die_at_s && stalls.empty() && floods.empty() && jumps.empty() && lag_s == 0.0; }
  bool dead(double t_s) const { return die_at_s && t_s >= *die_at_s; }
  bool stalled(double t_s) const;
  bool flooding(double t_s) const;
  // The clock error at simulated time t: the sum of the jumps at or before t.
  TimeNs clock_error_ns(double t_s) const;
};

}  // namespace luxloc
