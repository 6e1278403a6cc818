#pragma once
// Attitude and heading reference: Mahony's nonlinear complementary filter (SEEDS.md C.3).
// Gravity (and, with a magnetometer, north) seen by the body is compared with the same
// directions predicted from the current attitude; the cross product is the error e, and the
// gyro is corrected with g = gyro + kp e + ki integral(e) before it is integrated.
// Frames: world ENU, body FLU; q rotates body vectors into the world (R_BtoW).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/common/samples.hpp"

namespace luxloc {

struct MahonyOptions {
  double kp = 1.0;               // proportional gain (rad/s per unit error)
  double ki = 0.02;              // integral gain: learns the gyro bias
  double kp_init = 10.0;         // high gain while converging after start
  double init_duration_s = 2.0;  // how long kp_init applies
  bool use_magnetometer = true;  // ignored when samples carry no magnetometer
  // Accelerometer readings whose norm departs from g by more than this fraction are not
  // used as a gravity reference (the device is accelerating).
  double acc_rejection = 0.15;
  double max_dt_s = 0.1;         // a larger gap is a dropout: integrate no further than this
  double gravity = 9.80665;
};

class MahonyFilter {
 public:
  explicit MahonyFilter(const MahonyOptions& options = {});

  // Initial alignment at rest (SEEDS.md C.1): roll and pitch from the accelerometer, yaw
  // from the tilt-compensated magnetometer (0 without one).
  void align(const Eigen::Vector3d& acc_inB, const Eigen::Vector3d* mag_inB);
  // One IMU sample; the first sample aligns. Non-finite samples are ignored (counted).
  void update(const ImuSample& s);

  bool initialized() const { return initialized_; }
  const Eigen::Quaterniond& q_BtoW() const { return q_; }
  Eigen::Matrix3d R_BtoW() const { return q_.toRotationMatrix(); }
  double yaw() const;    // heading of body x, CCW from east
  double roll() const;   // ZYX Euler
  double pitch() const;
  const Eigen::Vector3d& gyro_bias() const { return bias_; }  // ki's integral, rad/s
  Eigen::Vector3d gyro_corrected() const { return last_gyro_corrected_; }
  TimeNs time() const { return t_; }
  std::uint64_t rejected_samples() const { return rejected_; }
  const MahonyOptions& options() const { return options_; }

 private:
  MahonyOptions options_;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_gyro_corrected_ = Eigen::Vector3d::Zero();
  TimeNs t_ = 0;
  TimeNs t_start_ = 0;
  bool initialized_ = false;
  std::uint64_t rejected_ = 0;
};

}  // namespace luxloc
