#pragma once
// Builds the planar filter named by `--filter`.
#include <memory>
#include <string>
#include <vector>

#include "core/filter/particle_filter.hpp"
#include "core/filter/planar_filter.hpp"

namespace luxloc {

struct FilterSettings {
  std::string name = "pf";
  ParticleFilterOptions pf;
};

std::vector<std::string> filter_names();
// Throws std::invalid_argument for an unknown name.
std::unique_ptr<PlanarFilter> make_planar_filter(const FilterSettings& settings);

}  // namespace luxloc
