#pragma once
// Bounded lock-free single-producer / single-consumer ring buffer.
//
// Why our own: each pipeline edge has exactly one producer thread (a source, or the
// fusion stage) and one consumer (the fusion stage, or the output thread). An SPSC ring
// needs only two atomics with acquire/release ordering, never allocates after
// construction and never takes a lock. TBB's concurrent_bounded_queue is MPMC and blocks
// through a monitor; boost::lockfree is not among our Debian dependencies. Capacity is a
// power of two; head and tail sit on separate cache lines to avoid false sharing, and each
// side caches the other's index so the common case touches one shared line.
#include <atomic>
#include <cstddef>
#include <memory>
#include <new>
#include <optional>
#include <stdexcept>
#include <utility>

namespace luxloc {

template <typename T>
class SpscQueue {
 public:
  explicit SpscQueue(std::size_t min_capacity) {
    std::size_t cap = 2;
    while (cap < min_capacity) cap <<= 1;
    capacity_ = cap;
    mask_ = cap - 1;
    slots_ = std::make_unique<std::optional<T>[]>(cap);
  }
  SpscQueue(const SpscQueue&) = delete;
  SpscQueue& operator=(const SpscQueue&) = delete;

  std::size_t capacity() const { return capacity_; }

  // Producer side. False when full (the item is left untouched).
  bool try_push(T&& item) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_cache_ == capacity_) {
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail - head_cache_ == capacity_) return false;
    }
    slots_[tail & mask_].emplace(std::move(item));
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  // Consumer side. Empty optional when there is nothing to take.
  std::optional<T> try_pop() {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_cache_) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head == tail_cache_) return std::nullopt;
    }
    std::optional<T> out = std::move(slots_[head & mask_]);
    slots_[head & mask_].reset();
    head_.store(head + 1, std::memory_order_release);
    return out;
  }

  // Consumer side: the oldest item without removing it (nullptr when empty). Valid until
  // the next try_pop().
  const T* peek() {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_cache_) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head == tail_cache_) return nullptr;
    }
    return &*slots_[head & mask_];
  }

  std::size_t size_approx() const {
    return tail_.load(std::memory_order_acquire) - head_.load(std::memory_order_acquire);
  }

 private:
  static constexpr std::size_t kLine = 64;
  std::size_t capacity_ = 0;
  std::size_t mask_ = 0;
  std::unique_ptr<std::optional<T>[]> slots_;
  alignas(kLine) std::atomic<std::size_t> head_{0};  // written by the consumer
  std::size_t tail_cache_ = 0;                      // consumer's copy of tail_
  alignas(kLine) std::atomic<std::size_t> tail_{0};  // written by the producer
  std::size_t head_cache_ = 0;                      // producer's copy of head_
};

}  // namespace luxloc
