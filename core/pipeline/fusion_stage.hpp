#pragma once
// The one stage that sees every sample, in timestamp order, on one thread.
#include <vector>

#include "core/common/pose.hpp"
#include "core/common/samples.hpp"

namespace luxloc {

class FusionStage {
 public:
  virtual ~FusionStage() = default;
  // Consumes one sample; appends the poses it produces (if any) to `out`.
  virtual void process(const Sample& sample, std::vector<PoseEstimate>& out) = 0;
  // End of all streams: flush whatever is pending.
  virtual void finish(std::vector<PoseEstimate>& /*out*/) {}
};

}  // namespace luxloc
