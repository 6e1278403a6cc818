#include "core/filter/filter_factory.hpp"

#include <stdexcept>

namespace luxloc {

std::vector<std::string> filter_names() { return {"pf", "gpf", "ekf"}; }

std::unique_ptr<PlanarFilter> make_planar_filter(const FilterSettings& settings) {
  if (settings.name == "pf") return std::make_unique<ParticleFilter>(settings.pf);
  if (settings.name == "gpf") {
    ParticleFilterOptions o = settings.pf;
    o.policy = ResamplingPolicy::Genetic;
    o.resample_every_correction = true;  // seed B resamples at every observation
    return std::make_unique<ParticleFilter>(o);
  }
  if (settings.name == "ekf") return std::make_unique<EkfFilter>(settings.ekf);
  throw std::invalid_argument("unknown filter '" + settings.name + "'");
}

}  // namespace luxloc
