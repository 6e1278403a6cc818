#include "core/sim/mag_disturbance.hpp"

#include <cmath>
#include <stdexcept>

namespace luxloc::sim {

Eigen::Vector3d MagneticField::at(const Eigen::Vector3d& p_inW, double t_s) const {
  Eigen::Vector3d m = earth_inW;
  for (const SteelAnomaly& s : steel) {
    const double d2 = (p_inW.head<2>() - s.centre_inW).squaredNorm();
    m += s.delta_ut * std::exp(-d2 / (2.0 * s.radius_m * s.radius_m));
  }
  for (const MagnetPass& g : magnets) {
    const double u = (t_s - g.t_peak_s) / g.sigma_s;
    m += g.delta_ut * std::exp(-0.5 * u * u);
  }
  return m;
}

std::vector<std::string> mag_disturbance_names() { return {"none", "steel", "magnet", "both"}; }

MagneticField make_magnetic_field(const std::string& disturbance, const Eigen::Vector3d& earth_inW,
                                  const Trajectory& trajectory, double duration_s) {
  MagneticField f;
  f.earth_inW = earth_inW;
  const bool steel = disturbance == "steel" || disturbance == "both";
  const bool magnet = disturbance == "magnet" || disturbance == "both";
  if (!steel && !magnet && disturbance != "none")
    throw std::invalid_argument("unknown magnetic disturbance '" + disturbance + "' (none, steel, magnet, both)");
  if (steel) {
    // Beside the path, to the walker's left: the field at the pillar is turned by ~25 deg in
    // the horizontal and 14 % weaker (8, -5, 6 uT on 0, 22, -42): the size of the anomalies
    // measured next to steel columns in office buildings (tens of percent, tens of degrees).
    const BodyState s = trajectory.state(0.3 * duration_s);
    const Eigen::Vector2d left(-std::sin(s.yaw), std::cos(s.yaw));
    SteelAnomaly a;
    a.centre_inW = s.p_BinW.head<2>() + 0.4 * left;
    a.radius_m = 0.8;
    a.delta_ut = {8.0, -5.0, 6.0};
    f.steel.push_back(a);
  }
  if (magnet) {
    // A magnet carried past: 25 uT east at the peak turns the horizontal field by ~49 deg
    // and raises |m| by 13 %, for ~2 s (sigma 0.7 s).
    MagnetPass g;
    g.t_peak_s = 0.6 * duration_s;
    g.sigma_s = 0.7;
    g.delta_ut = {25.0, 0.0, 0.0};
    f.magnets.push_back(g);
  }
  return f;
}

}  // namespace luxloc::sim
