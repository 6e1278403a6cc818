#pragma once
// Hands every sample to a side stage (a recorder) before the main one (the fusion), so a
// live run can be recorded while it runs (`luxloc run --record DIR`). Poses come from the
// main stage only.
#include "core/pipeline/fusion_stage.hpp"

namespace luxloc {

class TeeStage final : public FusionStage {
 public:
  TeeStage(FusionStage& side, FusionStage& main) : side_(side), main_(main) {}
  void process(const Sample& sample, std::vector<PoseEstimate>& out) override {
    std::vector<PoseEstimate> ignored;
    side_.process(sample, ignored);
    main_.process(sample, out);
  }
  void finish(std::vector<PoseEstimate>& out) override {
    std::vector<PoseEstimate> ignored;
    side_.finish(ignored);
    main_.finish(out);
  }

 private:
  FusionStage& side_;
  FusionStage& main_;
};

}  // namespace luxloc
