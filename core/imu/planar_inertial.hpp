#pragma once
// Planar strapdown integration, the motion model of SEEDS.md B.2 ("heading += omega dt;
// position += displacement along heading") done in the world frame with the full attitude
// (SEEDS.md C.2): the specific force rotated by R_BtoW, minus gravity, is integrated twice
// in the horizontal plane. Consumer accelerometers make this drift within seconds, so it is
// meant to be reset by the filter: set_velocity() from the filter's estimate, take() the
// displacement since the previous take() for each prediction. At rest (StillDetector) the
// velocity is set to zero (a zero-velocity update), which bounds the drift between walks.
#include <Eigen/Core>
#include <optional>

#include "core/common/samples.hpp"
#include "core/imu/still_detector.hpp"

namespace luxloc {

struct PlanarInertialOptions {
  double gravity = 9.80665;
  bool zero_velocity_at_rest = true;
  StillOptions still;
  double max_dt_s = 0.1;  // a longer gap is a dropout: integrate no further than this
};

struct PlanarIncrement {
  TimeNs t0 = 0, t1 = 0;                              // span covered
  Eigen::Vector2d dp_inW = Eigen::Vector2d::Zero();   // displacement, world x/y (m)
  double dyaw_rad = 0.0;                              // heading change
  Eigen::Vector2d v_inW = Eigen::Vector2d::Zero();    // velocity at t1
  bool at_rest = false;                               // the device was still at t1
};

class PlanarInertialIntegrator {
 public:
  explicit PlanarInertialIntegrator(const PlanarInertialOptions& options = {});

  // One IMU sample and the attitude at its time (body FLU -> world ENU).
  void update(const ImuSample& s, const Eigen::Matrix3d& R_BtoW);
  // The displacement accumulated since the previous take() (or the start), then restarts.
  PlanarIncrement take();
  void set_velocity(const Eigen::Vector2d& v_inW) { v_inW_ = v_inW; }
  const Eigen::Vector2d& velocity() const { return v_inW_; }
  bool at_rest() const { return still_.still(); }

 private:
  PlanarInertialOptions options_;
  StillDetector still_;
  std::optional<TimeNs> t_last_;
  std::optional<double> yaw_last_;
  Eigen::Vector2d v_inW_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d a_last_ = Eigen::Vector2d::Zero();
  PlanarIncrement acc_;
  bool started_ = false;
};

}  // namespace luxloc
