#include "core/pipeline/pipeline.hpp"

#include <limits>
#include <memory>
#include <thread>

#include "core/common/memory_trim.hpp"
#include "core/pipeline/clock_rebase.hpp"
#include "core/pipeline/doorbell.hpp"
#include "core/pipeline/source_lag.hpp"
#include "core/pipeline/source_silence.hpp"
#include "core/pipeline/spsc_queue.hpp"

namespace luxloc {
namespace {

using Clock = std::chrono::steady_clock;

struct QueuedSample {
  Sample sample;
  Clock::time_point arrival;
  std::size_t bytes = 0;  // pixel memory it holds (frames), for the lane's byte budget
};

std::size_t payload_bytes(const SensorData& d) {
  const auto* f = std::get_if<FrameSample>(&d);
  return f ? f->gray.total() * f->gray.elemSize() : 0;
}

struct Lane {
  explicit Lane(std::size_t capacity) : queue(capacity) {}
  SpscQueue<QueuedSample> queue;
  std::atomic<bool> done{false};
  std::atomic<std::size_t> bytes{0};  // pixel memory queued (PipelineOptions::source_queue_bytes)
  std::uint64_t fused = 0;  // touched by the fusion thread only
  DropCounts drops;         // the pipeline's own drops for this source
  std::string failure;      // written by the source thread before `done`
  std::uint64_t clock_jumps = 0;  // source thread, read after the join
  TimeNs first_jump_ns = 0;
  bool end_seen = false;  // fusion thread: the end was noted
  bool tracks_lag = false;  // a live source stamped on the arrival clock
  SourceLag lag;            // fusion thread
};

TimeNs as_ns(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

void shift_time(SensorData& d, TimeNs offset) {
  std::visit([offset](auto& s) { s.t += offset; }, d);
}

// A live source's clock that jumps is re-based onto the arrival clock (ClockRebase).
void rebase_clock(ClockRebase& clock, SensorData& d, Clock::time_point arrival, Lane& lane) {
  const TimeNs t = sample_time(d);
  const TimeNs fixed = clock.apply(t, as_ns(arrival));
  if (fixed != t) shift_time(d, fixed - t);
  if (clock.jumped() && lane.clock_jumps++ == 0) lane.first_jump_ns = clock.last_jump_ns();
}

}  // namespace

Pipeline::Pipeline(std::vector<SourcePtr> sources, std::vector<PoseSinkPtr> sinks, PipelineOptions options)
    : sources_(std::move(sources)), sinks_(std::move(sinks)), options_(std::move(options)) {}

Pipeline::~Pipeline() = default;

PipelineReport Pipeline::run(FusionStage& stage) {
  const auto wall0 = Clock::now();
  const std::size_t n = sources_.size();
  std::vector<std::unique_ptr<Lane>> lanes;
  for (std::size_t i = 0; i < n; ++i) {
    lanes.push_back(std::make_unique<Lane>(options_.source_queue_capacity));
    lanes.back()->tracks_lag = sources_[i]->live() && sources_[i]->clock_follows_arrival();
  }
  SpscQueue<PoseEstimate> poses(options_.pose_queue_capacity);
  std::atomic<bool> fusion_done{false};
  // Who sleeps on what when its ring is empty (or full): the fusion thread on input_bell
  // (a source pushed or ended), the output thread on pose_bell (poses, or the end), a
  // playback source on space_bell (the fusion thread took a sample), the fusion thread on
  // pose_space_bell (the output thread took a pose).
  Doorbell input_bell, pose_bell, space_bell, pose_space_bell;
  std::atomic<std::uint64_t> poses_written{0}, poses_dropped{0};
  std::string sink_failure;
  LatencyHistogram latency;  // the output thread's

  // --- one thread per source ---
  std::vector<std::thread> source_threads;
  for (std::size_t i = 0; i < n; ++i) {
    source_threads.emplace_back([this, i, &lanes, &input_bell, &space_bell] {
      Source& src = *sources_[i];
      Lane& lane = *lanes[i];
      const TimeNs offset = i < options_.clock_offsets_ns.size() ? options_.clock_offsets_ns[i] : 0;
      const bool rebase = src.live() && src.clock_follows_arrival();
      ClockRebase clock;
      IdleWait backoff;
      try {
        SensorData d;
        while (!stop_.load(std::memory_order_relaxed) && src.next(d)) {
          if (offset != 0) shift_time(d, offset);
          const auto arrival = Clock::now();
          if (rebase) rebase_clock(clock, d, arrival, lane);
          const std::size_t bytes = payload_bytes(d);
          QueuedSample item{Sample{sample_time(d), static_cast<int>(i), std::move(d)}, arrival, bytes};
          backoff.reset();
          // Full: no slot, or the frames queued already hold the lane's byte budget (one
          // frame always fits, whatever its size).
          auto over_budget = [&] {
            const std::size_t queued = lane.bytes.load(std::memory_order_acquire);
            return bytes > 0 && queued > 0 && queued + bytes > options_.source_queue_bytes;
          };
          auto try_push = [&] {
            if (over_budget()) return false;
            lane.bytes.fetch_add(bytes, std::memory_order_acq_rel);  // before the consumer can pop it
            if (lane.queue.try_push(std::move(item))) return true;
            lane.bytes.fetch_sub(bytes, std::memory_order_acq_rel);
            return false;
          };
          for (;;) {
            const std::uint64_t ticket = space_bell.ticket();
            if (try_push()) {
              input_bell.ring();
              break;
            }
            if (options_.live) {
              lane.drops.add("queue full", src.name() + ": fusion stage fell behind");
              break;
            }
            if (stop_.load(std::memory_order_relaxed)) break;
            backoff.wait(space_bell, ticket);
          }
          d = SensorData{};
        }
        lane.failure = src.failure();
      } catch (const std::exception& e) {
        lane.failure = e.what();
      }
      lane.done.store(true, std::memory_order_release);
      input_bell.ring();
    });
  }

  // --- output thread: sinks never run on the fusion thread ---
  std::thread output_thread([&] {
    IdleWait backoff;
    // A sink that fails (disk full, closed pipe) is written no more and stops the run
    // (like a signal: every pose computed so far still goes to the other sinks); its file
    // keeps every complete row (TextFile).
    std::vector<bool> failed(sinks_.size(), false);
    auto sink_failed = [&](std::size_t k, const std::exception& e) {
      failed[k] = true;
      if (sink_failure.empty()) sink_failure = sinks_[k]->name() + ": " + e.what();
      stop_.store(true, std::memory_order_relaxed);
    };
    auto drain_one = [&]() {
      std::optional<PoseEstimate> p = poses.try_pop();
      if (!p) return false;
      pose_space_bell.ring();
      if (p->input_arrival_ns != 0) {
        p->latency_s = 1e-9 * static_cast<double>(as_ns(Clock::now()) - p->input_arrival_ns);
        latency.add(p->latency_s);
      }
      for (std::size_t k = 0; k < sinks_.size(); ++k) {
        if (failed[k]) continue;
        try {
          sinks_[k]->write(*p);
        } catch (const std::exception& e) {
          sink_failed(k, e);
        }
      }
      poses_written.fetch_add(1, std::memory_order_relaxed);
      return true;
    };
    while (true) {
      const std::uint64_t ticket = pose_bell.ticket();
      if (drain_one()) {
        backoff.reset();
        continue;
      }
      if (fusion_done.load(std::memory_order_acquire)) {
        while (drain_one()) {
        }
        break;
      }
      backoff.wait(pose_bell, ticket);
    }
    for (std::size_t k = 0; k < sinks_.size(); ++k) {
      if (failed[k]) continue;
      try {
        sinks_[k]->flush();
      } catch (const std::exception& e) {
        sink_failed(k, e);
      }
    }
  });

  // --- fusion: merge by timestamp on this thread ---
  PipelineReport report;
  std::vector<PoseEstimate> out;
  SourceSilence silence([&] {
    std::vector<std::string> names;
    for (const auto& src : sources_) names.push_back(src->name());
    return names;
  }());
  std::int64_t newest_arrival_ns = 0;  // of the samples fused so far
  auto emit = [&] {
    if (out.empty()) return;
    for (auto& p : out) {
      silence.annotate(p);
      p.input_arrival_ns = newest_arrival_ns;
      IdleWait b;
      for (;;) {
        const std::uint64_t ticket = pose_space_bell.ticket();
        if (poses.try_push(std::move(p))) break;
        if (options_.live) {
          poses_dropped.fetch_add(1, std::memory_order_relaxed);
          break;
        }
        pose_bell.ring();  // the output thread may be asleep with a full ring
        b.wait(pose_space_bell, ticket);
      }
    }
    pose_bell.ring();
    out.clear();
  };
  TimeNs last_t = std::numeric_limits<TimeNs>::min();
  std::uint64_t fused_total = 0;
  bool have_first = false;
  TimeNs first_t = 0;
  IdleWait backoff;
  const TimeNs max_lag_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(options_.max_source_lag).count();
  MemoryTrim trim;  // a backlog of frames must not stay in the RSS (core/common/memory_trim.hpp)
  while (!stop_.load(std::memory_order_relaxed)) {
    const std::uint64_t ticket = input_bell.ticket();
    int best = -1;
    TimeNs best_t = 0;
    bool waiting = false, any_open = false;
    TimeNs waited_lag = -1;  // the largest learnt lag of the sources waited for (ns)
    for (std::size_t i = 0; i < n; ++i) {
      Lane& lane = *lanes[i];
      const bool done = lane.done.load(std::memory_order_acquire);
      const QueuedSample* head = lane.queue.peek();
      if (done && !head && !lane.end_seen) {
        lane.end_seen = true;
        if (!lane.failure.empty()) silence.on_lost(i);
      }
      if (head) {
        any_open = true;
        if (best < 0 || head->sample.t < best_t) {
          best = static_cast<int>(i);
          best_t = head->sample.t;
        }
      } else if (!done) {
        any_open = true;
        waiting = true;
        // A lag beyond max_source_lag is not waited for (the samples would be late anyway;
        // or the source stamps on a clock of its own, where "lag" means nothing).
        if (lane.tracks_lag && lane.lag.known() && lane.lag.high_ns() <= max_lag_ns)
          waited_lag = std::max(waited_lag, lane.lag.high_ns());
      }
    }
    if (!any_open) break;  // every source ended and every queue is empty
    if (best < 0) {
      backoff.wait(input_bell, ticket);
      continue;
    }
    if (waiting) {
      // A source may still deliver something older than `best`.
      if (!options_.live) {
        backoff.wait(input_bell, ticket);
        continue;
      }
      // A sample stamped before `best` may still be on its way: wait the reorder window
      // beyond the head's arrival, or beyond the moment a lagging source's sample of the
      // head's time usually arrives (its stamp + the source's learnt lag), up to
      // max_source_lag after the head's arrival.
      const QueuedSample* head = lanes[static_cast<std::size_t>(best)]->queue.peek();
      auto expected = head->arrival;
      if (waited_lag >= 0) {
        const Clock::time_point lagged{std::chrono::duration_cast<Clock::duration>(std::chrono::nanoseconds(best_t + waited_lag))};
        expected = std::clamp(lagged, head->arrival, head->arrival + options_.max_source_lag);
      }
      const auto give_up = expected + options_.reorder_window;
      if (Clock::now() < give_up) {
        backoff.wait(input_bell, ticket, give_up);
        continue;
      }
    }
    backoff.reset();
    Lane& lane = *lanes[static_cast<std::size_t>(best)];
    QueuedSample item = std::move(*lane.queue.try_pop());
    if (item.bytes > 0) lane.bytes.fetch_sub(item.bytes, std::memory_order_release);
    space_bell.ring();
    if (lane.tracks_lag) lane.lag.update(item.sample.t, as_ns(item.arrival));
    if (item.sample.t < last_t) {
      lane.drops.add("late (older than the reorder window)",
                     sources_[static_cast<std::size_t>(best)]->name() + ": sample " +
                         std::to_string(ns_to_seconds(last_t - item.sample.t)) + " s behind");
      continue;
    }
    last_t = item.sample.t;
    if (sources_[static_cast<std::size_t>(best)]->live()) silence.on_sample(static_cast<std::size_t>(best), last_t);
    if (!have_first) {
      have_first = true;
      first_t = item.sample.t;
    }
    if (options_.realtime) {
      std::this_thread::sleep_until(wall0 + std::chrono::nanoseconds(item.sample.t - first_t));
      item.arrival = Clock::now();  // paced playback: a sample "arrives" when its time comes
    }
    ++lane.fused;
    newest_arrival_ns = std::max<std::int64_t>(
        newest_arrival_ns, as_ns(item.arrival));
    stage.process(item.sample, out);
    emit();
    std::size_t queued_bytes = 0;
    for (const auto& l : lanes) queued_bytes += l->bytes.load(std::memory_order_relaxed);
    trim.tick(queued_bytes);
    if (options_.probe && ++fused_total % PipelineOptions::kProbeEvery == 0) {
      PipelineProbe probe;
      probe.t = item.sample.t;
      probe.queue_wait_s = std::chrono::duration<double>(Clock::now() - item.arrival).count();
      for (const auto& l : lanes) probe.source_depths.push_back(l->queue.size_approx());
      probe.queued_frame_bytes = queued_bytes;  // summed for the trim just above
      probe.pose_depth = poses.size_approx();
      probe.fused = fused_total;
      options_.probe(probe);
    }
  }
  report.stopped = stop_.load(std::memory_order_relaxed);
  stage.finish(out);
  emit();
  fusion_done.store(true, std::memory_order_release);
  pose_bell.ring();

  // Unblock and join the sources (live ones may sit in a blocking read).
  if (report.stopped)
    for (auto& s : sources_) s->request_stop();
  for (auto& t : source_threads) t.join();
  output_thread.join();

  for (std::size_t i = 0; i < n; ++i) {
    SourceReport sr;
    sr.name = sources_[i]->name();
    sr.samples = lanes[i]->fused;
    sr.drops = sources_[i]->drops().snapshot();
    for (auto& [k, e] : lanes[i]->drops.snapshot()) sr.drops[k] = e;
    if (lanes[i]->lag.known()) {
      sr.lag_samples = lanes[i]->lag.count();
      sr.lag_mean_s = lanes[i]->lag.mean_s();
      sr.lag_max_s = lanes[i]->lag.max_s();
    }
    sr.failure = lanes[i]->failure;
    sr.silences = silence.gaps(i).count;
    sr.longest_silence_s = silence.gaps(i).longest_s;
    sr.clock_jumps = lanes[i]->clock_jumps;
    sr.first_clock_jump_s = ns_to_seconds(lanes[i]->first_jump_ns);
    report.sources.push_back(std::move(sr));
  }
  report.poses = poses_written.load();
  report.poses_dropped = poses_dropped.load();
  report.first_t = first_t;
  report.last_t = have_first ? last_t : first_t;
  report.wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();
  report.output_failure = sink_failure;
  report.latency = latency.summary();
  for (const auto& sink : sinks_) report.sinks.push_back({sink->name(), sink->drops().snapshot()});
  report.paced = options_.live || options_.realtime;
  return report;
}

}  // namespace luxloc
