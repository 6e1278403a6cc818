#pragma once
// Builds the planar filter named by `--filter`:
//   pf   SIR particle filter (SEEDS.md A), resampling by the options' scheme and trigger
//   gpf  genetic particle filter (SEEDS.md B): the particle filter with genetic
//        resampling (crossover + mutation) after every correction, as seed B does
//   ekf  extended Kalman filter over [px, py, vx, vy] (SEEDS.md C.6)
#include <memory>
#include <string>
#include <vector>

#include "core/filter/ekf_filter.hpp"
#include "core/filter/particle_filter.hpp"
#include "core/filter/planar_filter.hpp"

namespace luxloc {

struct FilterSettings {
  // A constructor rather than an aggregate, so FilterSettings{name, pf} stays warning-free.
  FilterSettings(std::string filter_name = "pf", ParticleFilterOptions pf_options = {}, EkfOptions ekf_options = {})
      : name(std::move(filter_name)), pf(std::move(pf_options)), ekf(ekf_options) {}
  std::string name;
  ParticleFilterOptions pf;  // pf, gpf
  EkfOptions ekf;            // ekf
};

std::vector<std::string> filter_names();
// Throws std::invalid_argument for an unknown name.
std::unique_ptr<PlanarFilter> make_planar_filter(const FilterSettings& settings);

}  // namespace luxloc
