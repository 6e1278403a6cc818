#include "app/compare_configs.hpp"

namespace luxloc::app {

const std::vector<CompareConfig>& compare_configs() {
  static const std::vector<CompareConfig> configs = {
      {"imu-only", "IMU dead reckoning after 3 s of absolute fixes",
       [](RunConfig& c) { c.fusion.absolute_for_s = 3.0; }},
      {"fixes-only", "absolute fixes, constant velocity (IMU: attitude)",
       [](RunConfig& c) {
         c.fusion.use_imu = false;
         c.coupling = "loose";
       }},
      {"pf-a", "seed A: SIR PF, Gaussian weights, resample each fix",
       [](RunConfig& c) {
         c.fusion.filter = "pf";
         c.coupling = "loose";
         c.uwb_likelihood = "gaussian";  // seed A's plain Gaussian weighting, no NLOS tail
         c.fusion.pf.resample_every_correction = true;
       }},
      {"gpf-b", "seed B: genetic PF (crossover + mutation)",
       [](RunConfig& c) {
         c.fusion.filter = "gpf";
         c.coupling = "loose";
         c.fusion.pf.genetic.preserve_spread = false;  // the seed's step as published (run --genetic-as-published)
       }},
      {"gpf", "genetic PF keeping mean and spread (--filter gpf)",
       [](RunConfig& c) { c.fusion.filter = "gpf"; }},
      {"ekf-c", "seed C: EKF [p, v], IMU prediction",
       [](RunConfig& c) {
         c.fusion.filter = "ekf";
         c.coupling = "loose";
       }},
      {"best", "run's defaults (PF, pdr, tight VLC, robust UWB)", [](RunConfig&) {}},
  };
  return configs;
}

}  // namespace luxloc::app
