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
//   alignment (steel, motors), or whose heading departs from the gyro-propagated heading by
//   more than a gate (a field that turns while the gyro does not), does not correct the
//   heading; a disturbance lasting longer than a timeout while the device moves becomes the
//   new reference (the device moved to another field); while it is still, never;
// - a heading loop of its own (kp_heading, ki_heading) that learns the gyro bias about the
//   vertical through the magnetometer while moving; every rejection is counted (rejections()).
// Defaults: measured on the simulator's walk and on the real fusion_ahrs log (docs/IMU.md).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "core/common/samples.hpp"
#include "core/imu/still_detector.hpp"

namespace luxloc {

struct MahonyOptions {
  // Gains: tuned on the simulator's walk, seeds 1-10, grades ideal/consumer/poor, clean and
  // disturbed field (scripts/yaw_table.sh 1 10), and checked on the real fusion_ahrs log;
  // reported on the hold-out seeds 101-120 (docs/IMU.md). Walking accelerations that pass
  // the acc_rejection test bias the gravity reference by ~0.5 deg, and through the dip
  // (tan 62 deg = 1.9) that becomes ~1 deg of heading: kp 0.3 -> 0.2 cut the ideal IMU's yaw
  // p95 from 1.38 to 1.16 deg; 0.1 cut it further (1.01) but doubled roll rms on the real
  // log (0.21 -> 0.55 deg: real hand-held motion needs the faster tilt loop).
  double kp = 0.2;               // proportional gain of the gravity error (rad/s per unit error)
  double ki = 0.005;             // integral gain of the gravity error: learns the roll/pitch-axis bias
  // Heading loop (magnetometer), its own gains: s^2 + kp_heading s + ki_heading = 0 for the
  // heading error, so the bias it learns settles with time constant ~kp_heading / ki_heading
  // (30 s; the old shared ki 0.005 took 60 s and more, since the magnetometer was rejected
  // in every turn). ki_heading 0.02 halved the yaw p50 of a walk without standstills and a
  // 0.8 deg/s bias (0.97 -> 0.59 deg, seed 5) but put real-log roll rms to 0.40 and yaw rms
  // to 1.24 deg (the log's magnetometer errors integrate into the bias): 0.01 is the middle.
  // Standstills (bias_at_rest) learn the bias in about a second; this loop is for walks without.
  double kp_heading = 0.3;
  double ki_heading = 0.01;
  double kp_init = 10.0;         // high gain while converging after start
  double init_duration_s = 2.0;  // how long kp_init applies
  bool use_magnetometer = true;  // ignored when samples carry no magnetometer
  // Accelerometer readings whose norm departs from g by more than this fraction are not
  // used as a gravity reference (the device is accelerating). Walking swings the norm by
  // +-2 m/s^2 about g; only the samples near g carry little horizontal acceleration.
  double acc_rejection = 0.05;
  // Magnetometer readings whose magnitude departs from the reference by more than this
  // fraction, or whose dip angle by more than mag_dip_rejection_rad, are not used...
  // 5 % / 10 deg / 3 deg: from 10 % / 10 deg / no heading gate, seeds 1-10 consumer with a
  // steel pillar and a magnet: yaw p95 8.0 -> 2.9 deg; clean field unchanged (no rejection).
  // On the real log the magnitude gate rejects 21 % of the samples (hand-held, imperfect
  // hard-iron calibration) and roll/pitch/yaw stay within 0.3 / 0.3 / 0.9 deg rms of Fusion.
  double mag_rejection = 0.05;
  double mag_dip_rejection_rad = 0.17;  // ~10 deg
  // ...or whose heading (the horizontal field direction in the world, through the current
  // attitude) is further than this from north: a field that turns while the gyro does not.
  double mag_heading_gate_rad = 0.052;  // ~3 deg
  // The gate widens by the heading error the gyro may have built since the magnetometer last
  // corrected it: (bias uncertainty + scale uncertainty |omega_z|) per second, shrinking at
  // kp_heading while the field is used. Without it a 2 % scale error (the poor grade) turns
  // the heading 1.8 deg in a corner and every corner of a fast walk reads as a disturbance.
  // 2 %: the poor grade's scale sigma; 0.2 deg/s: a bias the at-rest estimate left (a 1 s
  // standstill with a noisy gyro) or the heading loop has not yet learnt.
  double gyro_scale_uncertainty = 0.02;
  double gyro_bias_uncertainty_rps = 0.0035;
  // ...unless the disturbance lasts longer than this while the device moves: then its field
  // becomes the reference (the device moved to another field). A still device cannot have
  // moved to another field, so while it is still the clock does not run: a field that
  // changes or turns under a still gyro is a disturbance however long it lasts.
  double mag_rejection_timeout_s = 10.0;
  double max_dt_s = 0.1;  // a larger gap is a dropout: integrate no further than this
  double gravity = 9.80665;
  // Gyro bias at rest: while the StillDetector says the device is still, the bias estimate
  // is the mean gyro reading over the still run (the integrals are paused). Its 0.4 s window
  // means a 1 s standstill yields >= 60 samples of mean (noise / sqrt(60)).
  bool bias_at_rest = true;
  StillOptions still;
  // The bias at rest must not learn a slow smooth turn (a carried bag): the still test also
  // asks the magnetometer whether the field turns in the body (StillOptions::check_mag_turn).
  bool still_checks_mag_turn = true;
};

// The defaults, for code that wants to name them (`luxloc imu --help`, docs).
inline constexpr MahonyOptions kMahonyDefaults{};

// What the filter refused to use, and for how long (the sum of the sample intervals).
struct AhrsRejections {
  std::uint64_t acc_samples = 0;        // specific force off g: not a gravity reference
  double acc_s = 0.0;
  std::uint64_t mag_samples = 0;        // every rejected magnetometer sample, of which:
  double mag_s = 0.0;
  std::uint64_t mag_magnitude = 0;      // |m| off the reference
  std::uint64_t mag_dip = 0;            // dip off the reference
  std::uint64_t mag_heading = 0;        // heading innovation beyond the gate (the field turned)
  std::uint64_t mag_adopted = 0;        // lasting disturbances adopted as the new reference
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

  // Error-state feedback from the fusion (issue 11, core/fusion/heading_feedback.hpp): the
  // fusion's heading says this filter's yaw is off by dyaw (true = yaw() + dyaw) and that
  // it integrates a rate about the world vertical that is short by drate (rad/s). Turns the
  // attitude about the world vertical (roll and pitch are unchanged) and moves the gyro
  // bias along the body's view of the vertical. Non-finite values are ignored.
  void correct_heading(double dyaw_rad, double drate_rps);
  // While on, the magnetometer does not correct the heading (the fusion holds a better
  // one: the camera's; two heading references with integrators would wind up against each
  // other wherever the field is off by a degree). Its samples are then neither used nor
  // counted as rejected.
  void hold_magnetometer(bool on) { mag_held_ = on; }
  bool magnetometer_held() const { return mag_held_; }
  // Seconds since the magnetometer last corrected the heading (infinity: never).
  double since_mag_correction_s() const;

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
  std::uint64_t mag_rejected_samples() const { return rejections_.mag_samples; }
  const AhrsRejections& rejections() const { return rejections_; }
  // The last sample's verdicts (false before the first update).
  bool last_mag_rejected() const { return last_mag_rejected_; }
  bool last_acc_rejected() const { return last_acc_rejected_; }
  bool still() const { return still_.still(); }
  const MahonyOptions& options() const { return options_; }

 private:
  // Error term of the magnetometer (heading only), or zero when it is not to be used.
  Eigen::Vector3d magnetometer_error(const Eigen::Matrix3d& R, const ImuSample& s, double dt, bool converging);

 public:
  // The heading gate now: mag_heading_gate_rad plus the drift the gyro may have built.
  double mag_heading_gate_now() const { return options_.mag_heading_gate_rad + heading_drift_rad_; }

 private:
  void set_mag_reference(const Eigen::Vector3d& mag_inB, const Eigen::Vector3d& up_inB);

  MahonyOptions options_;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_gyro_corrected_ = Eigen::Vector3d::Zero();
  TimeNs t_ = 0;
  TimeNs t_start_ = 0;
  bool initialized_ = false;
  std::uint64_t rejected_ = 0;
  AhrsRejections rejections_;
  bool last_mag_rejected_ = false, last_acc_rejected_ = false;
  StillDetector still_;
  Eigen::Vector3d bias_before_still_ = Eigen::Vector3d::Zero();  // restored when a still run was a slow turn
  bool bias_from_rest_ = false;  // a still run that was rest (not a turn) has set the bias
  // Magnetic reference: magnitude (sensor units) and dip (angle below the horizon).
  bool mag_ref_valid_ = false;
  double mag_ref_norm_ = 0.0, mag_ref_dip_ = 0.0;
  double mag_disturbed_s_ = -1.0;  // moving time the field has been disturbed (< 0: it is not)
  bool mag_recovering_ = false;     // adopted a lasting field: heading gate off until it agrees
  double heading_drift_rad_ = 0.0;  // bound on the gyro's heading error since the field last corrected it
  TimeNs t_mag_used_ = 0;
  bool mag_used_ = false;
  bool mag_held_ = false;  // the field has corrected the heading at least once
};

}  // namespace luxloc
