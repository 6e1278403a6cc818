#pragma once
// One interface for the planar fusion filters (particle filter, EKF): predict with a
// motion input, correct with a measurement that carries its covariance and gate
// (robot_localization's shape). Planar state: position and velocity in the world (ENU).
#include <Eigen/Core>
#include <limits>

#include "core/common/time.hpp"

namespace luxloc {

// Pedestrian dead reckoning as a motion input (SEEDS.md A, S1: step length l_k, heading
// alpha_k), in continuous form: the walker moves at the gait speed l_k / T_k of the last
// step along the current heading, so the prediction does not lag a step behind and the
// displacement over a step is still l_k along the step's heading. The per-step noise
// (length, heading) comes with the input; the filters turn it into a rate over T_k.
struct GaitInput {
  double speed_mps = 0.0;          // forward speed (m/s), >= 0
  double heading_rad = 0.0;        // direction of walking, CCW from east (world ENU)
  double length_sigma_m = 0.0;     // 1 sigma of one step's length
  double heading_sigma_rad = 0.0;  // 1 sigma of one step's heading
  double step_period_s = 0.55;     // T_k: the per-step noise accrues over this time
  // Yaw rate about the vertical (rad/s): in turns walkers cut corners, slow down and step
  // off the device's heading by amounts no model of one walker knows (GaitNoise::turn_noise).
  double turn_rate_rps = 0.0;
  // The walker's turned angle paid out with the distance (GaitSpeed::turn_paid_rps, rad/s):
  // the particle filter's walker loses A metres per radian of it (GaitNoise::turn_slowdown_*),
  // speed = k s - A turn_paid; the EKF leaves turns to the gait model's own factor.
  double turn_paid_rps = 0.0;
};

// Motion between two IMU samples (or frames), over dt. Which fields count decides the
// motion model (see MotionModel, core/filter/motion_model.hpp):
//   has_gait: pedestrian dead reckoning, gait speed and heading (SEEDS.md A, S1);
//   has_acc:  planar strapdown, horizontal acceleration in the world from the attitude-
//             rotated specific force minus gravity (SEEDS.md B.2 / C.2);
//   neither:  constant velocity (no IMU; SEEDS.md C.6's prediction).
struct MotionInput {
  // MotionInput{dt, acc, has_acc} (strapdown / constant velocity) as before the gait input
  // came: a constructor, so the short form stays warning-free.
  MotionInput(double dt_s = 0.0, const Eigen::Vector2d& acc = Eigen::Vector2d::Zero(), bool acc_valid = false)
      : dt(dt_s), acc_inW(acc), has_acc(acc_valid) {}
  double dt = 0.0;
  Eigen::Vector2d acc_inW = Eigen::Vector2d::Zero();
  bool has_acc = false;
  bool has_gait = false;
  GaitInput gait;
  // Time since the heading was last fixed by an observation (s, at the start of this
  // interval): the yaw-offset state's drift grows with it (HeadingNoise::bias_sigma_rps).
  double heading_drift_s = 0.0;
  // > 0 while an absolute yaw reference bounds the AHRS's yaw error (its magnetometer
  // corrects it): the yaw offset then reverts to 0 with this stationary sigma (rad) instead
  // of walking without bound (HeadingNoise::bounded_rad, walker_bounded_rad;
  // FusionEngine::predict_to picks one). 0: a random walk.
  double heading_bound_rad = 0.0;
  // A displacement every hypothesis takes alike (m, world): the device swinging round its
  // holder's turning axis as the heading changes (core/imu/lever_arm.hpp), on top of the
  // body's motion above.
  Eigen::Vector2d shift_inW = Eigen::Vector2d::Zero();
};

// An absolute 2-D position measurement (a VLC fix, a UWB position, fixes.csv).
struct PositionMeasurement {
  TimeNs t = 0;
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * 0.01;  // covariance, m^2
  double gate_sigma = 6.0;  // Mahalanobis gate against the filter's own spread
};

// A horizontal velocity measurement in the world frame (IMU-derived: a zero-velocity
// update from a still detector, a step-length/heading estimate, visual odometry).
struct VelocityMeasurement {
  TimeNs t = 0;
  Eigen::Vector2d v = Eigen::Vector2d::Zero();             // m/s
  Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * 0.01;  // covariance, (m/s)^2
  double gate_sigma = 6.0;
};

// A measurement a filter may use: finite value and a positive-definite covariance (checked
// as a positive determinant and first diagonal element, enough for 2x2). Every filter refuses
// (and counts) the others, so NaN from bad input never reaches a state.
inline bool usable(const Eigen::Vector2d& value, const Eigen::Matrix2d& R) {
  return value.allFinite() && R.allFinite() && R.determinant() > 0.0 && R(0, 0) > 0.0;
}
inline bool usable(const PositionMeasurement& m) { return usable(m.z, m.R); }
inline bool usable(const VelocityMeasurement& m) { return usable(m.v, m.R); }

struct CorrectionResult {
  bool accepted = false;
  bool reinitialized = false;  // the filter re-initialised around the fix (lost track)
  double mahalanobis = std::numeric_limits<double>::quiet_NaN();
};

struct PlanarEstimate {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  Eigen::Vector2d v = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov_p = Eigen::Matrix2d::Identity();
  double n_eff = std::numeric_limits<double>::quiet_NaN();  // particle filters only
  bool valid = false;
};

class PlanarFilter {
 public:
  virtual ~PlanarFilter() = default;
  virtual void initialize(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov_p) = 0;
  virtual bool initialized() const = 0;
  virtual void predict(const MotionInput& u) = 0;
  virtual CorrectionResult correct(const PositionMeasurement& m) = 0;
  // Filters that cannot use a velocity measurement refuse it (accepted = false).
  virtual CorrectionResult correct_velocity(const VelocityMeasurement&) { return {}; }
  virtual PlanarEstimate estimate() const = 0;
};

}  // namespace luxloc
