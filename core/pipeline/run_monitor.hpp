#pragma once
// What the live views of a run (MQTT status, web page) read of the running pipeline from
// the output thread or their own threads: the sources' names, their sample counters
// (CountingStage) and their drop counters. The counters are atomics or thread-safe
// DropCounts; the sources own their DropCounts and outlive the sinks (Pipeline destroys
// its sinks first).
#include <memory>
#include <string>
#include <vector>

#include "core/common/drop_counts.hpp"
#include "core/pipeline/counting_stage.hpp"

namespace luxloc {

struct RunMonitor {
  std::vector<std::string> source_names;
  std::shared_ptr<const SampleCounters> counters;
  std::vector<const DropCounts*> source_drops;  // indexed like source_names; may be empty
};

}  // namespace luxloc
