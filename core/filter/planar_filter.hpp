#pragma once
// One interface for the planar fusion filters (particle filter, EKF): predict with a
// motion input, correct with a measurement that carries its covariance and gate
// (robot_localization's shape). Planar state: position and velocity in the world (ENU).
#include <Eigen/Core>
#include <limits>

#include "core/common/time.hpp"

namespace luxloc {

// Motion between two IMU samples: horizontal acceleration in the world from the
// strapdown (attitude-rotated, gravity removed), over dt.
struct MotionInput {
  double dt = 0.0;
  Eigen::Vector2d acc_inW = Eigen::Vector2d::Zero();
  bool has_acc = false;  // false: constant-velocity prediction
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
