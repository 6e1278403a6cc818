#include <catch2/catch.hpp>
#include <thread>
#include <vector>

#include "core/pipeline/spsc_queue.hpp"

using luxloc::SpscQueue;

TEST_CASE("SpscQueue is bounded and FIFO", "[pipeline]") {
  SpscQueue<int> q(3);
  REQUIRE(q.capacity() == 4);
  for (int i = 0; i < 4; ++i) REQUIRE(q.try_push(int{i}));
  int extra = 99;
  REQUIRE_FALSE(q.try_push(std::move(extra)));
  REQUIRE(extra == 99);  // a refused item is left untouched
  REQUIRE(*q.peek() == 0);
  for (int i = 0; i < 4; ++i) REQUIRE(*q.try_pop() == i);
  REQUIRE_FALSE(q.try_pop().has_value());
  REQUIRE(q.peek() == nullptr);
}

TEST_CASE("SpscQueue passes a million items between two threads in order", "[pipeline]") {
  SpscQueue<std::uint64_t> q(64);
  constexpr std::uint64_t kN = 1'000'000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kN; ++i)
      while (!q.try_push(std::uint64_t{i})) std::this_thread::yield();
  });
  std::uint64_t expected = 0, bad = 0;
  while (expected < kN) {
    if (auto v = q.try_pop()) {
      if (*v != expected) ++bad;
      ++expected;
    }
  }
  producer.join();
  REQUIRE(bad == 0);
  REQUIRE(expected == kN);
}
