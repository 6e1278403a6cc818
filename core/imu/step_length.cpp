#include "core/imu/step_length.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace luxloc {

StepLengthKind parse_step_length_kind(const std::string& name) {
  if (name == "weinberg") return StepLengthKind::weinberg;
  if (name == "cadence") return StepLengthKind::cadence;
  if (name == "constant") return StepLengthKind::constant;
  throw std::invalid_argument("unknown step-length model '" + name + "' (valid: weinberg, cadence, constant)");
}

double StepLengthModel::length_m(const DetectedStep& step) const {
  double l = options_.a_m;
  switch (options_.kind) {
    case StepLengthKind::weinberg:
      l = options_.weinberg_k * std::pow(std::max(step.swing(), 0.0), 0.25);
      break;
    case StepLengthKind::cadence:
      if (step.interval_s > 0.0) l = options_.a_m + options_.b_m_s * (1.0 / step.interval_s - 1.79);
      break;
    case StepLengthKind::constant:
      break;
  }
  return std::clamp(l, options_.min_m, options_.max_m);
}

double StepLengthModel::calibrate_weinberg(const std::vector<DetectedStep>& steps, double distance_m) {
  double sum = 0.0;
  for (const DetectedStep& s : steps) sum += std::pow(std::max(s.swing(), 0.0), 0.25);
  return sum > 0.0 ? distance_m / sum : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace luxloc
