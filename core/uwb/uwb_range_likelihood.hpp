#pragma once
// Tight coupling of UWB into the particle filter (the pattern of
// core/fusion/reprojection_likelihood.hpp): a particle at (x, y) predicts the 3-D distance
// to the anchor (and, with an AOA, the bearing from it); the log-likelihood of the measured
// values comes from UwbNoiseModel (robust NLOS tail or plain Gaussian). One range to one
// anchor is a usable update (a ring); range + AOA to one base station is seed B's fix,
// weighed without first turning it into a position (no d -> r conversion blow-up under
// the anchor, no Gaussian approximation of the ring segment).
#include <Eigen/Core>
#include <cmath>

#include "core/uwb/uwb_noise_model.hpp"

namespace luxloc {

class UwbRangeLikelihood {
 public:
  // aoa_rad NaN: range only.
  UwbRangeLikelihood(const Eigen::Vector3d& p_AinW, double z_B, double range_m, double aoa_rad,
                     const UwbNoiseModel& noise)
      : ax_(p_AinW.x()), ay_(p_AinW.y()), dz2_((z_B - p_AinW.z()) * (z_B - p_AinW.z())),
        range_(range_m), aoa_(aoa_rad), has_aoa_(std::isfinite(aoa_rad)), noise_(noise) {}

  // log p(measurement | body at (x, y, z_B)), normalised densities (comparable across
  // measurements, which the gate uses).
  double operator()(double x, double y) const {
    const double dx = x - ax_, dy = y - ay_;
    const double e_r = range_ - std::sqrt(dx * dx + dy * dy + dz2_);
    if (!has_aoa_) return noise_.range_log_likelihood(e_r);
    return noise_.range_aoa_log_likelihood(e_r, aoa_ - std::atan2(dy, dx));
  }

  // Range residual (measured - predicted, m) and bearing residual (rad) at (x, y).
  double range_residual(double x, double y) const {
    const double dx = x - ax_, dy = y - ay_;
    return range_ - std::sqrt(dx * dx + dy * dy + dz2_);
  }
  double bearing_residual(double x, double y) const {
    return has_aoa_ ? UwbNoiseModel::wrap(aoa_ - std::atan2(y - ay_, x - ax_)) : 0.0;
  }
  double horizontal_distance(double x, double y) const { return std::hypot(x - ax_, y - ay_); }
  bool has_aoa() const { return has_aoa_; }

 private:
  double ax_, ay_, dz2_, range_, aoa_;
  bool has_aoa_;
  UwbNoiseModel noise_;
};

}  // namespace luxloc
