#pragma once
// Turns the discrete steps of pedestrian dead reckoning (SEEDS.md A, S1: l_k, alpha_k)
// into a forward speed at any instant, for a filter that predicts at the IMU rate.
//
// A step is confirmed StepDetectorOptions::min_interval_s after its heel strike, so
// applying l_k when it is known would lag the walker by that much plus a whole step.
// Instead the walked distance is extrapolated from the last heel strike at the walking pace
// (the median of the last steps' l_k / T_k: a walker keeps its pace), for at most one step
// period plus the confirmation delay. While extrapolating, the speed is scaled by the bounce
// of the vertical acceleration (its RMS over one step) relative to the bounce seen at the steps:
// a walker who slows down to stop bounces less, one who stopped does not bounce (the
// extrapolation then ends). The output speed is the rate of that extrapolation plus a
// servo (time constant servo_tau_s) onto it of the distance already output, so the
// total output distance follows the sum of the step lengths.
//
// Within a step the walker's speed changes (slowing into a turn, the sway of each step)
// faster than steps can tell. The horizontal acceleration along the heading sees it: its
// integral, high-passed with accel_blend_tau_s (so the step speed keeps the long term and
// an accelerometer bias cannot run away) and with its slow mean removed, is added to the
// speed (a complementary filter: steps for the low frequencies, the accelerometer for the
// high ones).
//
// Walkers slow down in turns, at the same cadence (shorter steps): with turn_slowdown_s_per_rad
// c > 0 every step length and the extrapolation are scaled by 1 - c |omega| (omega: the yaw
// rate averaged over turn_window_s, floored at min_turn_factor). The simulator's walker
// gives c = 0.21 s/rad (speed 1.24 m/s straight, 0.91 m/s at 1.25 rad/s); the fusion's
// step-length scale calibrates what is left.
//
// Beside the distance, the angle the walker turned is paid out in step with it (turn_paid):
// each step's turned angle (|omega| integrated over the step), the extrapolation's |omega|,
// and the same servo. A model whose walker loses A metres per radian of turn (the particle
// filter's turn slowdown, core/filter/motion_model.hpp GaitNoise::turn_slowdown0) subtracts
// A times this rate from the speed, and the loss lands on the steps that turned, not on the
// steps the servo happens to pay out after them.
#include <cstdint>
#include <deque>

#include "core/common/time.hpp"
#include "core/imu/pdr.hpp"

namespace luxloc {

struct GaitSpeedOptions {
  double servo_tau_s = 0.25;            // catch-up time constant of the output distance
  double nominal_step_s = 0.55;         // step period when a step has no known interval
  double bounce_window_s = 0.4;         // RMS window of the vertical acceleration (< a step: lag)
  double bounce_rms_mps2 = 0.3;         // below: the walker is not walking (extrapolation ends)
  double bounce_ref_weight = 0.3;       // EMA weight of each step's bounce in the reference
  bool scale_by_bounce = true;          // slow the extrapolation as the bounce fades
  double extrapolation_margin_s = 0.1;  // beyond T_k + the confirmation delay
  double max_speed_mps = 2.5;
  double accel_blend_tau_s = 0.3;       // complementary filter crossover; <= 0: steps only
  double turn_slowdown_s_per_rad = 0.2;  // c; 0: step length independent of turning
  double turn_window_s = 0.55;           // EMA time constant of |omega|
  double min_turn_factor = 0.5;
  double accel_mean_tau_s = 0.0;        // > 0: remove a slow mean of the along-track acceleration
  // The turned angle paid out with the distance (turn_paid_rps): owed distance beyond
  // turn_owed_min_m carries the owed angle (5 cm: a tenth of the shortest step); otherwise
  // |omega| over the pace, the pace taken as at least turn_min_pace_mps (0.3 m/s, below the
  // slowest walker's 0.49) so a walk's first short steps do not turn any yaw rate into a large
  // angle per metre; at most max_turn_per_m (10 rad/m: a full turn within 0.6 m).
  double turn_owed_min_m = 0.05;
  double turn_min_pace_mps = 0.3;
  double max_turn_per_m = 10.0;
  // A step is confirmed confirmation_delay_s after its heel strike; the walk since the heel
  // strike is then taken at the step's pace scaled by the bounce over that time (as the
  // extrapolation is), not at the full pace. A walker's last step before a stop is confirmed
  // while the walker decelerates, the bounce already fading. At the full pace every stop in
  // the dark ran long (sim --walker random --blackout 30:60, tuning seeds 1-12, 20 stops: the
  // distance from 2.5 s before to 1.5 s after each stop +0.078 m on average, rms 0.114, up
  // to 0.28 m); scaled by the bounce +0.011 m, rms 0.066. false: the full pace.
  bool catch_up_by_bounce = true;
  // The extrapolation (and, with catch_up_by_bounce, the catch-up above; without it the
  // catch-up keeps the last step's full pace) runs at the walking pace, the median of the
  // last pace_median_steps steps' paces (the bounce it is scaled against is likewise the
  // steps' average), not at the last step's pace. The last step's own pace carries a ramp:
  // a walk's first step has a short Weinberg length (its bounce was small) and no interval
  // (nominal period), so scaling it by the rising bounce again ran the extrapolation at half
  // the walker's speed, and the next step's catch-up then jumped the track 0.3-0.5 m ahead in
  // a few tenths of a second (tuning blackout seed 16, a start while an LED was in view:
  // 0.12 m off with a 2 cm sigma). A median, not a mean: a session's first steps include a
  // pace from a short interval (world seed 25: an exponential average of the paces carried it
  // and the walk ran at twice its speed into the dark, 0.9 m off; the median of 5: 0.4 m).
  // false: the last step's pace.
  bool extrapolate_at_reference_pace = true;
  int pace_median_steps = 5;
};

class GaitSpeed {
 public:
  explicit GaitSpeed(const GaitSpeedOptions& options = {}, double confirmation_delay_s = 0.3);

  // Every IMU sample: its time, the vertical acceleration in the world (gravity removed)
  // and the horizontal acceleration along the walking direction.
  void update(TimeNs t, double a_up_mps2, double a_along_mps2 = 0.0, double yaw_rate_rps = 0.0);
  double turn_factor() const;  // 1 - c |omega|, floored
  // A step, as PedestrianDeadReckoning::pop_step() returns it (Step::t = heel strike),
  // after the update() of the sample that confirmed it.
  void add_step(const Step& step);
  // The speed to integrate over [t0, t1] (one prediction; call in time order, t1 at or
  // shortly after the last update()); the output distance advances by speed (t1 - t0).
  double take_speed(TimeNs t0, TimeNs t1);
  // The turned angle paid out over the last take_speed() interval, per second (rad/s, >= 0).
  double turn_paid_rps() const { return turn_paid_rps_; }
  // Steps are coming: the last heel strike lies within the extrapolation horizon and the
  // walker still bounces.
  bool stepping() const { return extrapolating_; }
  // Another motion model covered the distance so far: no catch-up for it.
  void sync() {
    output_m_ = expected_m();
    output_turn_ = expected_turn();
  }

  double walked_m() const { return steps_m_; }   // sum of step lengths
  double output_m() const { return output_m_; }  // distance handed out so far
  double expected_m() const { return steps_m_ + extrapolated_m_; }
  double expected_turn() const { return steps_turn_ + extrapolated_turn_; }  // rad
  bool walking() const;                          // bounce above bounce_rms_mps2
  double bounce_rms() const;
  // The last step's period (for the motion noise) and the step itself.
  double step_period_s() const { return period_s_; }
  const Step& last_step() const { return last_; }
  bool has_step() const { return have_step_; }

 private:
  double rate_factor() const;  // bounce now / bounce at the steps, in [0, 1]
  double extrapolation_pace() const;

  GaitSpeedOptions options_;
  double confirmation_delay_s_;
  std::deque<std::pair<TimeNs, double>> bounce_;  // a_up over the RMS window
  double bounce_sum2_ = 0.0;
  double bounce_ref_ = 0.0;  // EMA of the bounce RMS at step confirmations
  TimeNs t_ = 0;
  bool have_t_ = false;
  double steps_m_ = 0.0;        // distance walked up to the last heel strike
  double extrapolated_m_ = 0.0; // beyond it
  bool extrapolating_ = false;
  Step last_;
  bool have_step_ = false;
  double period_s_ = 0.55;
  double speed_mps_ = 0.0;      // l_k / T_k of the last step
  double pace_ref_ = 0.0;       // the walking pace: median of the recent l_k / T_k
  std::deque<double> recent_paces_;
  double output_m_ = 0.0;
  double accel_speed_mps_ = 0.0;  // high-passed integral of the along-track acceleration
  double accel_mean_mps2_ = 0.0;  // its slow mean (bias, attitude leak)
  double abs_yaw_rate_ = 0.0;     // EMA of |omega|
  double turn_integral_ = 0.0;    // integral of turn_factor() dt since the start
  // (t, turn_integral_, abs_turn_integral_, pace_integral_) over a few steps
  struct TurnMark {
    TimeNs t;
    double factor, angle, pace;
  };
  std::deque<TurnMark> turn_history_;
  double turn_integral_at(TimeNs t, double TurnMark::*field) const;
  double abs_turn_integral_ = 0.0;  // integral of the averaged |omega| dt since the start (rad)
  double pace_integral_ = 0.0;      // integral of rate_factor() turn_factor() dt since the start (s)
  double steps_turn_ = 0.0;         // angle turned up to the last heel strike (rad)
  double extrapolated_turn_ = 0.0;  // beyond it
  double output_turn_ = 0.0;
  double turn_paid_rps_ = 0.0;
};

}  // namespace luxloc
