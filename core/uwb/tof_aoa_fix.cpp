#include "core/uwb/tof_aoa_fix.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

std::optional<PositionMeasurement> tof_aoa_fix(const UwbSample& s, const Eigen::Vector3d& p_AinW, double z_B,
                                               const UwbNoiseModel& noise) {
  if (!std::isfinite(s.aoa_rad) || !std::isfinite(s.range_m) || s.range_m < 0.0 || !p_AinW.allFinite())
    return std::nullopt;
  const double dz = z_B - p_AinW.z();
  // A range shorter than the height difference (noise near the point under the anchor):
  // the device is (about) under it.
  const double r = std::sqrt(std::max(0.0, s.range_m * s.range_m - dz * dz));
  const Eigen::Vector2d u(std::cos(s.aoa_rad), std::sin(s.aoa_rad));
  PositionMeasurement m;
  m.t = s.t;
  m.z = p_AinW.head<2>() + r * u;
  // dr/dd = d / r grows without bound under the anchor: cap it, and never below the
  // range noise itself.
  const double gain = std::min(5.0, s.range_m / std::max(r, 1e-3));
  const double sr = std::max(noise.range_sigma_m, gain * noise.range_sigma_m);
  const double st = std::max(noise.range_sigma_m, r * noise.aoa_sigma_rad);
  const Eigen::Vector2d n(-u.y(), u.x());
  m.R = sr * sr * u * u.transpose() + st * st * n * n.transpose();
  return m;
}

}  // namespace luxloc
