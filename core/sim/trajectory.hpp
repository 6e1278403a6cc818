#pragma once
// Ground-truth motion of the device body (FLU) in the world (ENU): pose and its exact
// time derivatives at any time, which the IMU synthesiser and the frame renderer sample.
#include <Eigen/Geometry>
#include <vector>

namespace luxloc::sim {

struct BodyState {
  double t = 0.0;
  Eigen::Vector3d p_BinW = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_BinW = Eigen::Vector3d::Zero();  // world velocity, m/s
  Eigen::Vector3d a_BinW = Eigen::Vector3d::Zero();  // world acceleration (no gravity), m/s^2
  Eigen::Matrix3d R_BtoW = Eigen::Matrix3d::Identity();
  Eigen::Vector3d omega_inB = Eigen::Vector3d::Zero();  // body angular rate, body axes, rad/s
  // ZYX Euler angles: R_BtoW = Rz(yaw) Ry(pitch) Rx(roll); yaw is SPEC's heading of body x.
  double yaw = 0.0, pitch = 0.0, roll = 0.0;

  Eigen::Isometry3d T_BtoW() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R_BtoW;
    T.translation() = p_BinW;
    return T;
  }
};

// Builds a BodyState from ZYX Euler angles and their rates: R = Rz(yaw) Ry(pitch) Rx(roll),
// omega_inB = [roll' - yaw' sin(pitch);
//              pitch' cos(roll) + yaw' cos(pitch) sin(roll);
//              yaw' cos(pitch) cos(roll) - pitch' sin(roll)].
void set_attitude_zyx(BodyState& s, double yaw, double pitch, double roll, double yaw_rate,
                      double pitch_rate, double roll_rate);

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual BodyState state(double t_s) const = 0;
  // Heel-strike times of the walker's steps within [0, until_s] (empty when not walking).
  virtual std::vector<double> step_times(double until_s) const = 0;
};

// Standing perfectly still: a fixed pose, zero velocity and rate.
class StaticTrajectory final : public Trajectory {
 public:
  StaticTrajectory(const Eigen::Vector3d& p_BinW, double yaw, double pitch = 0.0, double roll = 0.0);
  BodyState state(double t_s) const override;
  std::vector<double> step_times(double) const override { return {}; }

 private:
  BodyState s_;
};

}  // namespace luxloc::sim
