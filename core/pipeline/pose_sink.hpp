#pragma once
// An output for fused poses (CSV/TUM file, UDP...). Sinks run on the output thread,
// never on the fusion thread, so a slow sink cannot block the filter.
#include <memory>
#include <string>

#include "core/common/drop_counts.hpp"
#include "core/common/pose.hpp"

namespace luxloc {

class PoseSink {
 public:
  virtual ~PoseSink() = default;
  virtual std::string name() const = 0;
  virtual void write(const PoseEstimate& pose) = 0;
  // Flush buffered output (called at the end and on SIGINT).
  virtual void flush() {}
  // Poses not delivered (no UDP receiver, full socket buffer, unwritable pose...) by reason.
  const DropCounts& drops() const { return drops_; }
  DropCounts& drops() { return drops_; }

 private:
  DropCounts drops_;
};

using PoseSinkPtr = std::unique_ptr<PoseSink>;

}  // namespace luxloc
