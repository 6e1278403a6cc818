#pragma once
// The one-line live status on stderr (`luxloc run`, on when stderr is a terminal, or
// --status on): data time and a progress bar when the session's span is known, rate per
// source, LEDs in view, filter spread, mode, latency p50/p99 (live) — redrawn in place at most 4 times a second,
// ended with a newline by flush(). A pose sink, so it runs on the output thread and never
// slows the filter.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/pipeline/counting_stage.hpp"
#include "core/pipeline/latency_stats.hpp"
#include "core/pipeline/pose_sink.hpp"

namespace luxloc {

class StatusLine final : public PoseSink {
 public:
  // `span_s` > 0: the playback's data span (progress bar); `t0`: its first time stamp.
  StatusLine(std::vector<std::string> source_names, std::shared_ptr<const SampleCounters> counters,
             double span_s = 0.0, TimeNs t0 = 0, std::FILE* out = stderr);
  std::string name() const override { return "status"; }
  void write(const PoseEstimate& pose) override;
  void flush() override;
  // The line for a pose, as drawn (for tests).
  std::string render(const PoseEstimate& pose, double wall_s);

 private:
  std::vector<std::string> names_;
  std::shared_ptr<const SampleCounters> counters_;
  double span_s_;
  TimeNs t0_;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_draw_{};
  std::vector<std::uint64_t> last_counts_;
  double last_wall_s_ = 0.0;
  std::vector<double> rates_;
  bool drawn_ = false;
  bool pending_ = false;  // a pose arrived after the last drawing
  PoseEstimate last_pose_;
  std::size_t last_len_ = 0;
  LatencyWindow latency_;  // of the last poses: p50 / p99 on the line
};

// First and last time stamps over a session folder's sensor CSVs (first data row and last
// line of each, without reading the files through); false when none can be read.
bool session_time_span(const std::string& dir, TimeNs& t_first, TimeNs& t_last);

}  // namespace luxloc
