#include "core/sim/trajectory.hpp"

#include <cmath>
#include <numbers>

namespace luxloc::sim {

void set_attitude_zyx(BodyState& s, double yaw, double pitch, double roll, double yaw_rate,
                      double pitch_rate, double roll_rate) {
  s.yaw = std::remainder(yaw, 2.0 * std::numbers::pi);  // (-pi, pi]
  s.pitch = pitch;
  s.roll = roll;
  s.R_BtoW = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
              Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                 .toRotationMatrix();
  const double sr = std::sin(roll), cr = std::cos(roll), sp = std::sin(pitch), cp = std::cos(pitch);
  s.omega_inB = {roll_rate - yaw_rate * sp, pitch_rate * cr + yaw_rate * cp * sr,
                 yaw_rate * cp * cr - pitch_rate * sr};
}

StaticTrajectory::StaticTrajectory(const Eigen::Vector3d& p_BinW, double yaw, double pitch, double roll) {
  s_.p_BinW = p_BinW;
  set_attitude_zyx(s_, yaw, pitch, roll, 0.0, 0.0, 0.0);
}

BodyState StaticTrajectory::state(double t_s) const {
  BodyState s = s_;
  s.t = t_s;
  return s;
}

}  // namespace luxloc::sim
