#pragma once
// The live view's events (Server-Sent Events text) in a bounded ring shared by every
// browser: the output thread pushes, each HTTP thread reads from its own position. A
// reader that falls more than the ring's capacity behind has lost events and is dropped
// (lagging()), so no client is ever buffered without bound and the writer never waits.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace luxloc {

class EventRing {
 public:
  explicit EventRing(std::size_t capacity) : capacity_(capacity) {}

  // The output thread's side: never blocks beyond the mutex (held for a push).
  void push(std::string event) {
    {
      std::lock_guard lock(mutex_);
      events_.push_back(std::move(event));
      if (events_.size() > capacity_) events_.pop_front();
      ++next_;
    }
    ready_.notify_all();
  }
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  // Sequence number the next push will get; a new reader starts here.
  std::uint64_t next() const {
    std::lock_guard lock(mutex_);
    return next_;
  }
  // The events from `from` on, waiting up to `timeout` for the first; `from` advances.
  // False when the reader fell behind the ring (events lost: drop it) or the ring closed.
  bool read(std::uint64_t& from, std::vector<std::string>& out, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [&] { return closed_ || next_ > from; });
    if (closed_) return false;
    const std::uint64_t oldest = next_ - events_.size();
    if (from < oldest) return false;
    for (std::uint64_t s = from; s < next_; ++s) out.push_back(events_[static_cast<std::size_t>(s - oldest)]);
    from = next_;
    return true;
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::string> events_;
  std::uint64_t next_ = 0;
  bool closed_ = false;
};

}  // namespace luxloc
