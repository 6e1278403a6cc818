#pragma once
// SEEDS.md B.3: a single base station's time of flight and angle of arrival give a
// position:  x = x_b + r cos(theta),  y = y_b + r sin(theta).
// The radio measures the 3-D distance d (uwb.csv's range_m = c0 * tau); with the known
// heights of the anchor and the device, the horizontal range is r = sqrt(d^2 - dz^2).
// Covariance: range noise along the bearing (scaled by dr/dd = d / r), bearing noise
// across it (r * sigma_theta).
#include <optional>

#include "core/common/samples.hpp"
#include "core/filter/planar_filter.hpp"
#include "core/uwb/uwb_noise_model.hpp"

namespace luxloc {

// nullopt without a finite bearing or range.
std::optional<PositionMeasurement> tof_aoa_fix(const UwbSample& s, const Eigen::Vector3d& p_AinW, double z_B,
                                               const UwbNoiseModel& noise);

}  // namespace luxloc
