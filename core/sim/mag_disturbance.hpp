#pragma once
// Magnetic disturbances for the simulator's magnetometer (docs/SIMULATOR.md "IMU"): the
// Earth field plus
// - steel: a field that bends near a steel pillar beside part of the path, a Gaussian bump
//   in space, delta * exp(-|p_xy - c|^2 / (2 r^2)) (a pillar is a local, static anomaly);
// - magnet: a magnet carried past the device, a Gaussian bump in time,
//   delta * exp(-(t - t_peak)^2 / (2 sigma^2)) (the device itself need not move).
// Both add to the world field; neither is seen by the gyro, which is what a filter can use.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

struct SteelAnomaly {
  Eigen::Vector2d centre_inW = Eigen::Vector2d::Zero();  // m, on the floor plan
  double radius_m = 0.8;
  Eigen::Vector3d delta_ut = Eigen::Vector3d::Zero();  // added field at the centre, ENU
};

struct MagnetPass {
  double t_peak_s = 0.0;
  double sigma_s = 0.7;
  Eigen::Vector3d delta_ut = Eigen::Vector3d::Zero();  // added field at the peak, ENU
};

struct MagneticField {
  Eigen::Vector3d earth_inW{0.0, 22.0, -42.0};
  std::vector<SteelAnomaly> steel;
  std::vector<MagnetPass> magnets;

  bool disturbed() const { return !steel.empty() || !magnets.empty(); }
  Eigen::Vector3d at(const Eigen::Vector3d& p_inW, double t_s) const;
};

// "none", "steel", "magnet", "both".
std::vector<std::string> mag_disturbance_names();
// The field for a disturbance name, placed along the trajectory so that every scenario meets
// it: the pillar 0.4 m beside the path where the device is at 30 % of the duration, the magnet
// passing at 60 % of it. Throws std::invalid_argument for an unknown name.
MagneticField make_magnetic_field(const std::string& disturbance, const Eigen::Vector3d& earth_inW,
                                  const Trajectory& trajectory, double duration_s);

}  // namespace luxloc::sim
