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
#include <cstdint>

namespace luxloc {

class MemoryTrim {
 public:
  // 5 s: a trim costs ~1 ms (measured on a 90 MB heap); 0.02 % of the time. Memory comes back
  // within seconds of a backlog's end.
  explicit MemoryTrim(std::chrono::milliseconds every = std::chrono::milliseconds(5000)) : every_(every) {}
  // Cheap when called often: looks at the clock every 256th call.
  void tick() {
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
};

}  // namespace luxloc
