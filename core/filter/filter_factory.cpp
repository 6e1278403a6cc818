#include "core/filter/filter_factory.hpp"

#include <stdexcept>

namespace luxloc {

std::vector<std::string> filter_names() { return {"pf"}; }

std::unique_ptr<PlanarFilter> make_planar_filter(const FilterSettings& settings) {
  if (settings.name == "pf") return std::make_unique<ParticleFilter>(settings.pf);
  throw std::invalid_argument("unknown filter '" + settings.name + "'");
}

}  // namespace luxloc
