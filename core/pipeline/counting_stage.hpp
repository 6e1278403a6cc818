#pragma once
// Counts the samples of each source on their way into the fusion stage, for the live status
// line (rate per source). Counters are atomics written by the fusion thread and read by the
// output thread.
#include <atomic>
#include <memory>
#include <vector>

#include "core/pipeline/fusion_stage.hpp"

namespace luxloc {

class SampleCounters {
 public:
  explicit SampleCounters(std::size_t sources) : counts_(sources) {}
  void add(std::size_t source) {
    if (source < counts_.size()) counts_[source].fetch_add(1, std::memory_order_relaxed);
  }
  std::uint64_t count(std::size_t source) const { return counts_[source].load(std::memory_order_relaxed); }
  std::size_t size() const { return counts_.size(); }

 private:
  std::vector<std::atomic<std::uint64_t>> counts_;
};

class CountingStage final : public FusionStage {
 public:
  CountingStage(FusionStage& inner, std::shared_ptr<SampleCounters> counters)
      : inner_(inner), counters_(std::move(counters)) {}
  void process(const Sample& sample, std::vector<PoseEstimate>& out) override {
    counters_->add(static_cast<std::size_t>(sample.source));
    inner_.process(sample, out);
  }
  void finish(std::vector<PoseEstimate>& out) override { inner_.finish(out); }

 private:
  FusionStage& inner_;
  std::shared_ptr<SampleCounters> counters_;
};

}  // namespace luxloc
