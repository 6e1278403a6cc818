#pragma once
// A wake-up for a thread that found its lock-free rings empty. The fast path stays
// lock-free: ring() is one atomic increment and one atomic load, and takes the mutex only
// when a waiter is asleep. A waiter takes a ticket *before* it looks at its rings, so a
// ring between the look and the sleep is never lost (the ticket no longer matches).
//
// ring() is not async-signal-safe (it may lock): a signal handler only sets a flag, and
// waiters bound their sleep so they see it (IdleWait::kMaxSleep).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace luxloc {

class Doorbell {
 public:
  using Clock = std::chrono::steady_clock;

  std::uint64_t ticket() const { return rings_.load(std::memory_order_seq_cst); }

  void ring() {
    rings_.fetch_add(1, std::memory_order_seq_cst);
    if (sleepers_.load(std::memory_order_seq_cst) > 0) {
      std::lock_guard lock(mutex_);
      wake_.notify_all();
    }
  }

  // Sleeps until a ring() after `ticket` was taken, or `deadline`.
  void wait(std::uint64_t ticket, Clock::time_point deadline) {
    std::unique_lock lock(mutex_);
    sleepers_.fetch_add(1, std::memory_order_seq_cst);
    wake_.wait_until(lock, deadline, [&] { return rings_.load(std::memory_order_seq_cst) != ticket; });
    sleepers_.fetch_sub(1, std::memory_order_seq_cst);
  }

 private:
  std::atomic<std::uint64_t> rings_{0};
  std::atomic<int> sleepers_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
};

// Spin briefly, then yield, then sleep on a Doorbell: cheap when data is about to arrive,
// next to nothing when none comes (the spin/yield/50 us-sleep loop this replaces woke its
// threads ~20,000 times a second on an idle live run).
class IdleWait {
 public:
  using Clock = Doorbell::Clock;
  // Bounds a sleep, so that a stop flag set by a signal handler is seen within it.
  static constexpr std::chrono::milliseconds kMaxSleep{100};

  // `ticket`: bell.ticket(), taken before the caller found nothing to do.
  void wait(Doorbell& bell, std::uint64_t ticket, Clock::time_point deadline = Clock::time_point::max()) {
    if (++n_ < 64) return;
    if (n_ < 96) {
      std::this_thread::yield();
      return;
    }
    const auto cap = Clock::now() + kMaxSleep;
    bell.wait(ticket, std::min(deadline, cap));
  }
  void reset() { n_ = 0; }

 private:
  unsigned n_ = 0;
};

}  // namespace luxloc
