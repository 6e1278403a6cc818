#pragma once
// A sensor source: a pull iterator the pipeline drives from a thread of its own (the
// host owns threads and queues). Playback sources return false at the end of their file;
// live sources block until data arrives and return false once request_stop() is called
// or the device is lost (then failed() says why).
#include <memory>
#include <string>

#include "core/common/drop_counts.hpp"
#include "core/common/samples.hpp"

namespace luxloc {

class Source {
 public:
  virtual ~Source() = default;
  virtual std::string name() const = 0;
  // Next sample in this source's own time order; false at the end of the stream.
  virtual bool next(SensorData& out) = 0;
  // Live sources: unblock next() and make it return false. Called from another thread.
  virtual void request_stop() {}
  virtual bool live() const { return false; }
  // Live sources whose time stamps follow the monotonic clock at their arrival (stamped on
  // arrival, a driver clock on CLOCK_MONOTONIC, the simulator in real time): the pipeline
  // re-bases such a clock when it jumps (core/pipeline/clock_rebase.hpp). False for
  // playback and for a simulator running ahead of real time.
  virtual bool clock_follows_arrival() const { return live(); }
  // Non-empty when the stream ended through a failure (device lost, I/O error).
  virtual std::string failure() const { return {}; }
  // Samples skipped (bad rows, bad checksums...) by reason.
  const DropCounts& drops() const { return drops_; }
  DropCounts& drops() { return drops_; }

 private:
  DropCounts drops_;
};

using SourcePtr = std::unique_ptr<Source>;

}  // namespace luxloc
