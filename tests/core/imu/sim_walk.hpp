#pragma once
// Shared by the IMU tests: the simulator's 90 s walk (biased, noisy IMU + magnetometer),
// built once per test binary run.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

namespace luxloc::test {

struct SimWalk {
  sim::Simulator simulator;
  std::vector<ImuSample> imu;
};

inline const SimWalk& sim_walk(std::uint64_t seed = 1, const char* scenario = "walk") {
  static std::vector<std::pair<std::pair<std::uint64_t, std::string>, std::unique_ptr<SimWalk>>> cache;
  for (const auto& [key, w] : cache)
    if (key.first == seed && key.second == scenario) return *w;
  sim::SimOptions o;
  o.seed = seed;
  o.duration_s = 90.0;
  auto w = std::make_unique<SimWalk>(SimWalk{sim::Simulator(sim::make_scenario(scenario), o), {}});
  w->imu = w->simulator.imu_samples();
  cache.emplace_back(std::make_pair(seed, std::string(scenario)), std::move(w));
  return *cache.back().second;
}

}  // namespace luxloc::test
