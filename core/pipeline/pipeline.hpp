#pragma once
// The streaming pipeline: every source on its own thread feeding a bounded lock-free SPSC
// queue; one fusion thread merging the queues in timestamp order; one output thread
// draining the poses to the sinks, so a slow sink never blocks the filter.
//
// Ordering: in playback every source is already time-ordered, so the merger waits until
// each live queue has a head item (or its source has ended) and takes the oldest: exact
// order. Live sources cannot be waited on forever: the merger waits at most the reorder
// window for a silent source, then moves on; a sample that arrives older than what was
// already fused is dropped and counted ("late").
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/common/drop_counts.hpp"
#include "core/pipeline/fusion_stage.hpp"
#include "core/pipeline/latency_stats.hpp"
#include "core/pipeline/pose_sink.hpp"
#include "core/pipeline/source.hpp"

namespace luxloc {

// What the fusion thread sees of the queues (for the soak benchmark and monitoring).
struct PipelineProbe {
  TimeNs t = 0;               // the sample just fused
  double queue_wait_s = 0.0;  // how long it waited in its source's queue (wall clock)
  std::vector<std::size_t> source_depths;  // samples waiting per source
  std::size_t pose_depth = 0;              // poses waiting for the output thread
  std::size_t queued_frame_bytes = 0;      // camera pixels waiting in the source queues (all lanes)
  std::uint64_t fused = 0;                 // samples fused so far
};

struct PipelineOptions {
  std::size_t source_queue_capacity = 256;
  // Camera frames queued per source at most, in pixel bytes: 16 MiB is ~0.6 s of 720p at
  // 30 fps, 1.8 s of VGA. A backlog beyond it waits (playback) or is dropped as "queue full"
  // (live: a frame that old is no use to a real-time pose), so a fusion that falls behind
  // cannot pile up hundreds of frames (the soak's +13-19 % RSS, docs/RELIABILITY.md).
  std::size_t source_queue_bytes = std::size_t{16} << 20;
  std::size_t pose_queue_capacity = 16384;
  // Live: how long (wall clock) the merger waits for a silent source before going on,
  // beyond the lag that source's samples usually arrive with (core/pipeline/source_lag.hpp).
  std::chrono::milliseconds reorder_window{60};
  // Live: the longest learnt lag the merger waits for (beyond the head sample's arrival).
  // 500 ms: the shortest silence (core/pipeline/source_silence.hpp); a source later than that
  // is treated as silent, not waited for, so a stalled camera holds the poses back by half a
  // second at most.
  std::chrono::milliseconds max_source_lag{500};
  // Live mode: a full queue drops (counted) instead of making the producer wait.
  bool live = false;
  // Pace playback at the recorded speed.
  bool realtime = false;
  // Per-source clock offsets (ns), added to every sample's time (indexed like sources;
  // missing entries are 0). E.g. the camera-IMU time offset.
  std::vector<TimeNs> clock_offsets_ns;
  // Called on the fusion thread after every kProbeEvery-th fused sample (none: no cost).
  std::function<void(const PipelineProbe&)> probe;
  static constexpr std::uint64_t kProbeEvery = 1024;
};

struct SourceReport {
  std::string name;
  std::uint64_t samples = 0;  // handed to the fusion stage
  std::map<std::string, DropCounts::Entry> drops;  // source's own and the pipeline's
  std::string failure;
  // Live sources: times the source fell silent and came back (core/pipeline/source_silence),
  // the longest silence, and clock jumps re-based (core/pipeline/clock_rebase; the first
  // one's size, s, > 0 when the clock jumped ahead).
  std::uint64_t silences = 0;
  double longest_silence_s = 0.0;
  std::uint64_t clock_jumps = 0;
  double first_clock_jump_s = 0.0;
  // Live sources on the arrival clock: how long after its stamps the source's samples
  // arrived (s), mean and max over lag_samples samples, fused or late
  // (core/pipeline/source_lag.hpp); lag_samples = 0: not measured.
  std::uint64_t lag_samples = 0;
  double lag_mean_s = 0.0, lag_max_s = 0.0;
};

struct SinkReport {
  std::string name;
  std::map<std::string, DropCounts::Entry> drops;  // poses not delivered, by reason
};

struct PipelineReport {
  std::vector<SourceReport> sources;
  std::uint64_t poses = 0;
  std::uint64_t poses_dropped = 0;
  TimeNs first_t = 0, last_t = 0;  // span of fused samples
  double wall_s = 0.0;
  bool stopped = false;  // stop() was called (signal), or an output failed
  // Non-empty when a sink failed (disk full, closed pipe): that sink was written no more
  // and the run stopped; the other sinks got every pose.
  std::string output_failure;
  // Age of the newest input of each pose when it was handed to the sinks (LatencyHistogram).
  LatencySummary latency;
  std::vector<SinkReport> sinks;  // every output, with what it could not deliver
  bool paced = false;  // live or --realtime: the latency is the filter's (else queueing ahead)
  double data_span_s() const { return ns_to_seconds(last_t - first_t); }
};

class Pipeline {
 public:
  Pipeline(std::vector<SourcePtr> sources, std::vector<PoseSinkPtr> sinks, PipelineOptions options);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Runs to the end of every source (or until stop(), or until a sink fails); the fusion
  // stage runs on the calling thread. Every pose the stage produced before the end is
  // written and flushed.
  PipelineReport run(FusionStage& stage);
  // Thread-safe and async-signal-safe (sets an atomic flag only).
  void stop() { stop_.store(true, std::memory_order_relaxed); }
  const std::vector<SourcePtr>& sources() const { return sources_; }

 private:
  std::vector<SourcePtr> sources_;
  std::vector<PoseSinkPtr> sinks_;
  PipelineOptions options_;
  std::atomic<bool> stop_{false};
};

}  // namespace luxloc
