#pragma once
// Which live sources have gone silent, on the merged timeline, for the pose output's mode
// and the end-of-run report (issue 13: a source that dies or stalls must not stop the run;
// the poses say that they are made without it). Runs on the fusion thread.
//
// A source is silent when the merged timeline has moved on by more than its silence limit
// since its last sample: max(kMinSilenceNs, kSilenceIntervals x its typical interval), the
// typical interval being a running mean of its sample intervals below the limit (a gap does
// not teach itself). A source that ended with a failure is lost. A pose made while sources
// are silent or lost carries them in its mode: "dead-reckoning (sim:walk/frames silent)".
#include <cstdint>
#include <string>
#include <vector>

#include "core/common/pose.hpp"
#include "core/common/time.hpp"

namespace luxloc {

// 0.5 s: ten frames of a 20 fps camera, fifty IMU samples; shorter gaps are a sensor's
// normal jitter or a dropped sample. 10 intervals: a 1 Hz UWB tag is silent after 10 s.
inline constexpr TimeNs kMinSilenceNs = kNsPerSecond / 2;
inline constexpr int kSilenceIntervals = 10;

class SourceSilence {
 public:
  explicit SourceSilence(std::vector<std::string> names) : sources_(names.size()) {
    for (std::size_t i = 0; i < names.size(); ++i) sources_[i].name = std::move(names[i]);
  }
  // A sample of source i at merged time t.
  void on_sample(std::size_t i, TimeNs t);
  // Source i ended through a failure (device lost, injected death).
  void on_lost(std::size_t i) { sources_[i].lost = true; }
  // Appends the silent and lost sources at time `t` to the pose's mode.
  void annotate(PoseEstimate& pose) const;

  struct Gaps {
    std::uint64_t count = 0;  // silences that ended (the source came back)
    double longest_s = 0.0;
  };
  Gaps gaps(std::size_t i) const { return sources_[i].gaps; }

 private:
  struct State {
    std::string name;
    bool seen = false, lost = false;
    TimeNs last = 0;
    double mean_interval = 0.0;  // ns
    Gaps gaps;
  };
  TimeNs limit(const State& s) const;

  std::vector<State> sources_;
};

}  // namespace luxloc
