#include "core/pipeline/source_silence.hpp"

#include <algorithm>

namespace luxloc {

// Weight of one interval in the running mean (about the last 16 intervals).
constexpr double kIntervalWeight = 1.0 / 16.0;

TimeNs SourceSilence::limit(const State& s) const {
  return std::max<TimeNs>(kMinSilenceNs, static_cast<TimeNs>(kSilenceIntervals * s.mean_interval));
}

void SourceSilence::on_sample(std::size_t i, TimeNs t) {
  State& s = sources_[i];
  if (s.seen) {
    const TimeNs gap = t - s.last;
    if (gap > limit(s)) {
      ++s.gaps.count;
      s.gaps.longest_s = std::max(s.gaps.longest_s, ns_to_seconds(gap));
    } else if (gap > 0) {
      s.mean_interval = s.mean_interval == 0.0 ? static_cast<double>(gap)
                                               : s.mean_interval + kIntervalWeight * (static_cast<double>(gap) - s.mean_interval);
    }
  }
  s.seen = true;
  s.last = std::max(s.last, t);
  s.lost = false;
}

void SourceSilence::annotate(PoseEstimate& pose) const {
  std::string extra;
  for (const State& s : sources_) {
    const char* what = s.lost ? "lost" : (s.seen && pose.t - s.last > limit(s)) ? "silent" : nullptr;
    if (!what) continue;
    if (!extra.empty()) extra += "; ";
    extra += s.name + " " + what;
  }
  if (extra.empty()) return;
  pose.mode += (pose.mode.empty() ? "(" : " (") + extra + ")";
}

}  // namespace luxloc
