#pragma once
// Hands freed heap memory back to the system now and then (glibc malloc_trim), so the
// resident memory of a long run follows what is in use, not its highest point.
//
// Why: a camera frame (VGA 300 KB, 720p 900 KB) is allocated on its source's thread and
// freed on the fusion thread. glibc raises its mmap threshold above the frame size after the
// first frame is freed, so frames then come from the source thread's heap arena, and a
// moment when the fusion falls behind (a queue of 100+ frames: a re-initialisation, another
// process taking the CPU) grows that arena by tens of MB. The arena does not shrink while a
// live frame sits above the freed ones, so the RSS kept the high-water mark (+13-19 % in the
// 10-minute soak; docs/RELIABILITY.md "Soak"). Fixing the mmap threshold instead (every frame
// its own mapping) cost 3x the throughput in page faults and unmaps.
#include <chrono>
#include <cstddef>
#include <cstdint>

namespace luxloc {

// One heap arena for every thread (glibc M_ARENA_MAX = 1), unless MALLOC_ARENA_MAX says
// otherwise. glibc gives each new thread an arena of its own (up to 8 per core): a frame is
// allocated in its source thread's arena and freed on the fusion thread, TBB workers and
// the output thread have theirs, and the freed pages left among live allocations of the
// several arenas are what malloc_trim cannot hand back. In the 1 h soak (`bench soak
// --duration 3600 --every 60`) the RSS floor rose 106 -> 118 MB over the first half hour
// with the heap in live allocations flat at 39-42 MB; with one arena it stayed at 103-105
// MB (docs/RELIABILITY.md "Soak"). luxloc allocates little per sample (the particle arrays
// are reused), so the one arena's lock costs nothing measurable (bench pf, bench live).
// Called first thing in main; a no-op where the C library is not glibc.
void use_one_heap_arena();

class MemoryTrim {
 public:
  // 5 s: a trim costs ~1 ms (measured on a 90 MB heap); 0.02 % of the time. Memory comes back
  // within seconds of a backlog's end.
  explicit MemoryTrim(std::chrono::milliseconds every = std::chrono::milliseconds(5000)) : every_(every) {}
  // Cheap when called often: looks at the clock every 256th call. `queued_bytes`: the frame
  // pixels waiting in the queues now; when a backlog (>= kBacklogBytes) has drained (<=
  // kDrainedBytes) the heap is trimmed at once, not at the next 5 s tick: at 20x real time
  // (playback, the soak) 5 s of wall clock are 100 s of data, and the backlog's pages would
  // sit in the RSS all that while.
  void tick(std::size_t queued_bytes = 0) {
    if (queued_bytes >= kBacklogBytes) backlog_ = true;
    if (backlog_ && queued_bytes <= kDrainedBytes) {
      backlog_ = false;
      last_ = std::chrono::steady_clock::now();
      trim();
      return;
    }
    if ((++calls_ & 255u) != 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < every_) return;
    last_ = now;
    trim();
  }
  // Releases free heap pages of every arena now (no-op where the C library has no malloc_trim).
  void trim();

 private:
  std::chrono::milliseconds every_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
  std::uint32_t calls_ = 0;
  bool backlog_ = false;
  // A quarter of the pipeline's 16 MiB frame budget (13 VGA frames) is a backlog worth
  // handing back; 1 MiB (3 VGA frames) is a queue that has drained. Chosen by reasoning.
  static constexpr std::size_t kBacklogBytes = std::size_t{4} << 20;
  static constexpr std::size_t kDrainedBytes = std::size_t{1} << 20;
};

}  // namespace luxloc
