#pragma once
// Attitude and heading reference: Mahony's nonlinear complementary filter (SEEDS.md C.3).
// Gravity (and, with a magnetometer, north) seen by the body is compared with the same
// directions predicted from the current attitude; the cross product is the error e, and the
// gyro is corrected with g = gyro + kp e + ki integral(e) before it is integrated.
// Frames: world ENU, body FLU; q rotates body vectors into the world (R_BtoW).
//
// Additions to the textbook filter, each switchable in MahonyOptions:
// - gyro bias at rest: while a StillDetector says the device is still, the bias is the mean
//   gyro reading (ki cannot learn a bias about the vertical without a magnetometer);
// - accelerometer rejection: a specific force whose norm is off g is not a gravity reference;
// - magnetic rejection: a field whose magnitude or dip departs from the one seen at
//   alignment (steel, motors) does not correct the heading; a disturbance lasting longer than
//   a timeout becomes the new reference (the device moved to another field).
// Defaults: measured on the simulator's walk and on the real fusion_ahrs log (docs/IMU.md).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "core/common/samples.hpp"
#include "core/imu/still_detector.hpp"

namespace luxloc {

struct MahonyOptions {
  double kp = 0.3;               // proportional gain (rad/s per unit error): ~3 s time constant
  double ki = 0.005;             // integral gain: learns the gyro bias while moving
  double kp_init = 10.0;         // high gain while converging after start
  double init_duration_s = 2.0;  // how long kp_init applies
  bool use_magnetometer = true;  // ignored when samples carry no magnetometer
  // Accelerometer readings whose norm departs from g by more than this fraction are not
  // used as a gravity reference (the device is accelerating). Walking swings the norm by
  // +-2 m/s^2 about g; only the samples near g carry little horizontal acceleration.
  double acc_rejection = 0.05;
  // Magnetometer readings whose magnitude departs from the reference by more than this
  // fraction, or whose dip angle by more than mag_dip_rejection_rad, are not used...
  double mag_rejection = 0.10;
  double mag_dip_rejection_rad = 0.17;  // ~10 deg
  // ...unless the disturbance lasts longer than this: then its field becomes the reference.
  double mag_rejection_timeout_s = 10.0;
  double max_dt_s = 0.1;  // a larger gap is a dropout: integrate no further than this
  double gravity = 9.80665;
  // Gyro bias at rest: while the StillDetector says the device is still, the bias estimate
  // is the mean gyro reading over the still run (ki's integral is paused).
  bool bias_at_rest = true;
  StillOptions still;
};

class MahonyFilter {
 public:
  explicit MahonyFilter(const MahonyOptions& options = {});

  // Initial alignment at rest (SEEDS.md C.1): roll and pitch from the accelerometer, yaw
  // from the tilt-compensated magnetometer (0 without one).
  void align(const Eigen::Vector3d& acc_inB, const Eigen::Vector3d* mag_inB);
  // One IMU sample; the first sample aligns. Non-finite samples and samples whose time does
  // not advance are ignored (counted in rejected_samples()).
  void update(const ImuSample& s);

  bool initialized() const { return initialized_; }
  const Eigen::Quaterniond& q_BtoW() const { return q_; }
  Eigen::Matrix3d R_BtoW() const { return q_.toRotationMatrix(); }
  double yaw() const;    // heading of body x, CCW from east
  double roll() const;   // ZYX Euler
  double pitch() const;
  const Eigen::Vector3d& gyro_bias() const { return bias_; }  // rad/s
  Eigen::Vector3d gyro_corrected() const { return last_gyro_corrected_; }
  TimeNs time() const { return t_; }
  std::uint64_t rejected_samples() const { return rejected_; }
  // Magnetometer samples not used because the field looked disturbed.
  std::uint64_t mag_rejected_samples() const { return mag_rejected_; }
  bool still() const { return still_.still(); }
  const MahonyOptions& options() const { return options_; }

 private:
  // Error term of the magnetometer (heading only), or zero when it is not to be used.
  Eigen::Vector3d magnetometer_error(const Eigen::Matrix3d& R, const ImuSample& s);
  void set_mag_reference(const Eigen::Vector3d& mag_inB, const Eigen::Vector3d& up_inB);

  MahonyOptions options_;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_gyro_corrected_ = Eigen::Vector3d::Zero();
  TimeNs t_ = 0;
  TimeNs t_start_ = 0;
  bool initialized_ = false;
  std::uint64_t rejected_ = 0;
  std::uint64_t mag_rejected_ = 0;
  StillDetector still_;
  // Magnetic reference: magnitude (sensor units) and dip (angle below the horizon).
  bool mag_ref_valid_ = false;
  double mag_ref_norm_ = 0.0, mag_ref_dip_ = 0.0;
  TimeNs mag_disturbed_since_ = -1;
};

}  // namespace luxloc
