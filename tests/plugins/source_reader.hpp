#pragma once
// Collects what a Source produces on a thread of its own until it ends or `count` samples
// arrived, with each sample's arrival time (the live-source tests through socat ptys).
// T: SensorData (anything) or one sample type (std::get: a wrong type fails the test).
#include <atomic>
#include <chrono>
#include <thread>
#include <type_traits>
#include <vector>

#include "core/pipeline/source.hpp"

namespace luxloc::test {

template <class T = SensorData>
struct SourceReader {
  SourceReader(Source& s, std::size_t count) : source(s), thread([this, count] {
    SensorData d;
    while (samples.size() < count && source.next(d)) {
      if constexpr (std::is_same_v<T, SensorData>)
        samples.push_back(d);
      else
        samples.push_back(std::get<T>(d));
      arrival.push_back(std::chrono::steady_clock::now());
    }
    done = true;
  }) {}
  ~SourceReader() {
    if (thread.joinable()) {
      source.request_stop();
      thread.join();
    }
  }
  SourceReader(const SourceReader&) = delete;
  SourceReader& operator=(const SourceReader&) = delete;
  // True when the reader finished within `t` (and its thread is joined).
  bool join_within(std::chrono::milliseconds t) {
    const auto end = std::chrono::steady_clock::now() + t;
    while (!done && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!done) return false;
    thread.join();
    return true;
  }

  Source& source;
  std::vector<T> samples;
  std::vector<std::chrono::steady_clock::time_point> arrival;
  std::atomic<bool> done{false};
  std::thread thread;  // last: starts once the members above exist
};

}  // namespace luxloc::test
