#pragma once
// The motion input of the fusion's prediction (`luxloc run --motion`), built from the IMU
// and the attitude of each sample (core/filter/motion_model.hpp):
//   pdr        steps (StepDetector), their lengths (StepLengthModel) and the attitude's
//              heading (SEEDS.md A, S1), as a gait speed along the current heading
//              (GaitSpeed) with the per-step length and heading noise. Between walks:
//              zero velocity while the IMU is still, strapdown while it moves without
//              steps (the first step of a walk is only detected once walked; a trolley or
//              a robot has none), zero velocity again for a walker turning on the spot
//              (rotating, its specific force steady);
//   strapdown  the specific force rotated into the world minus gravity (SEEDS.md B.2, C.2);
//   cv         nothing from the IMU: constant velocity.
#include <Eigen/Core>
#include <array>
#include <vector>
#include <limits>
#include <optional>

#include "core/filter/motion_model.hpp"
#include "core/filter/planar_filter.hpp"
#include "core/imu/gait_gate.hpp"
#include "core/imu/gait_speed.hpp"
#include "core/imu/pdr.hpp"
#include "core/imu/lever_arm.hpp"
#include "core/imu/still_detector.hpp"

namespace luxloc {

struct MotionSourceOptions {
  MotionModel model = MotionModel::pdr;
  // Per-step length noise 5 % (PdrOptions' 10 % is for PDR alone): the fusion calibrates
  // the step-length scale, what is left per step is smaller (docs/MOTION.md, tuning).
  PdrOptions pdr = [] {
    PdrOptions p;
    p.length.sigma_fraction = 0.05;
    return p;
  }();
  GaitSpeedOptions gait;
  StillOptions still;  // pdr: zero velocity while still
  // pdr between steps: strapdown while the IMU moves (true), or zero velocity (false).
  bool strapdown_between_steps = true;
  // After a walk ends (no bounce), zero velocity for this long even if the IMU is not
  // still yet: the walker is coming to a stop, the strapdown velocity would be stale.
  double settle_s = 1.0;
  // A walker turning round on the spot has no steps and a turning gyro, so it failed the
  // still test and was integrated by strapdown: on the drawn walkers' turns on the spot in a
  // 15 s blackout (stop 28, tuning seeds 19, 25, 40, consumer IMU) a standing walker moved
  // 0.05-0.19 m in a 1-2 s turn and its sigma grew from 0.2 to 1 m. When the specific force
  // stays steady (StillDetector's accelerometer tests; its gyro tests left out) nothing
  // translates, and the position is held. Only for a walker (a step used, the gait gate
  // passed): a robot or a trolley on a smooth arc has a steady specific force as well.
  // A device held away from the turning axis sees the centripetal force and fails the
  // accelerometer test: strapdown, as before.
  bool hold_turning_in_place = true;
  // Standing still after a walk, the servo pays out what the last steps still owe (see
  // input_for). How much of it the walker really walked is a guess: on the default walker
  // dropping it lost ~0.2 m at every stop; on a drawn walker (`sim --walker random
  // --camera-mode 1280x720:45:200:70`, tuning seed 6) its last detected step came after the
  // bounce had died, 0.25 m were owed and none of it was walked, and the filter sat 0.2 m
  // past the stop for 8 s with a sigma of 5 cm. So the payout carries along-track noise
  // whose variance grows by f^2 x owed x (distance paid): f^2 owed^2 / 2 over a whole
  // payout, 1 sigma = f owed / sqrt(2) (0.5 x owed at f = 0.7: the two walkers above within
  // 2 sigma). 0: none.
  double stop_owed_sigma = 0.7;
  double gravity = 9.80665;
  // pdr under `--motion auto` (issue 16): steps reach the gait speed only once GaitGate has
  // seen a gait; until then (a drone, a robot: never) the model is strapdown while moving,
  // zero velocity while still, and nothing can walk away on vibration.
  bool gait_gate = false;
  GaitGateOptions gate;
  // A walker's device held off the body's turning axis (issue 12 part 1: `sim --walker
  // random` draws 0-0.4 m forward, up to 0.2 m aside) swings round every turn: a turn round
  // on the spot carries it along a half circle (up to 0.9 m), a corner along a wider or
  // narrower arc than the steps walk. The lever arm is learnt from turns on the spot
  // (LeverArm: no steps, no bounce, a walker seen before); once learnt, the gait and the
  // standing walker move the device by (R(psi1) - R(psi0)) l as the heading turns, and a turn
  // on the spot is held in place with it instead of integrated by strapdown. false: not
  // learnt (every hypothesis moves with the body alone).
  bool lever_arm = true;
  LeverArmOptions lever;
};

// What the last input was (pdr: which of its three regimes).
enum class MotionRegime { cv, strapdown, gait, still };
// The regime's name in the pose output's `motion` column (SPEC.md "Pose output").
const char* motion_regime_name(MotionRegime r);

class MotionSource {
 public:
  explicit MotionSource(const MotionSourceOptions& options = {});

  // One (calibrated) IMU sample and the attitude after it.
  void update(const ImuSample& s, const Eigen::Matrix3d& R_BtoW);
  // The input for a prediction over [t0, t1] (t1 at or just after the last update()).
  MotionInput input(TimeNs t0, TimeNs t1);

  MotionModel model() const { return options_.model; }
  const PedestrianDeadReckoning& pdr() const { return pdr_; }
  const GaitSpeed& gait() const { return gait_; }
  std::uint64_t steps() const { return pdr_.step_count(); }          // detected
  std::uint64_t steps_used() const { return steps_used_; }           // passed the gait gate
  std::uint64_t impact_samples() const { return pdr_.impact_samples(); }  // heel-strike impact samples replaced
  MotionRegime regime() const { return regime_; }
  // Seconds predicted in each regime (index: MotionRegime), the mode over time in short.
  const std::array<double, 4>& regime_seconds() const { return regime_s_; }
  bool gait_confirmed() const { return !options_.gait_gate || gate_.confirmed(); }
  // Seconds the position was held while the IMU turned (hold_turning_in_place).
  double turning_in_place_s() const { return turning_in_place_s_; }
  const LeverArm& lever_arm() const { return lever_; }

 private:
  MotionInput input_for(TimeNs t0, TimeNs t1);

  MotionSourceOptions options_;
  PedestrianDeadReckoning pdr_;
  GaitSpeed gait_;
  StillDetector still_;
  GaitGate gate_;
  LeverArm lever_;
  std::vector<Step> held_;  // steps before the gate's verdict (replayed when it confirms)
  std::array<double, 4> regime_s_{};
  double turning_in_place_s_ = 0.0;
  std::uint64_t steps_used_ = 0;
  MotionRegime regime_ = MotionRegime::cv;
  TimeNs t_last_stepping_ = std::numeric_limits<TimeNs>::min() / 2;
  bool valid_ = false;
  Eigen::Vector2d acc_inW_ = Eigen::Vector2d::Zero();
  double heading_rad_ = 0.0;
  double yaw_rate_ = 0.0;  // rad/s about the world vertical, last sample
  double device_yaw_ = 0.0;  // device yaw at the last sample (rad)
  std::optional<double> input_yaw_;  // device yaw at the last input() (the lever's shift)
};

}  // namespace luxloc
