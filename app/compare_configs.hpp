#pragma once
// The configurations `luxloc compare` runs, each a change to the run options: the seeds'
// methods (SEEDS.md A, B, C), the single-sensor baselines they compare against, and the
// default of `luxloc run` (the best one we know, README "Comparison").
#include <functional>
#include <string>
#include <vector>

#include "app/run_session.hpp"

namespace luxloc::app {

struct CompareConfig {
  std::string name;
  std::string description;
  std::function<void(RunConfig&)> apply;
};

const std::vector<CompareConfig>& compare_configs();

}  // namespace luxloc::app
