#pragma once
// The motion models the planar filters predict with (`luxloc run --motion`), and the
// process noise of the pedestrian model's calibration states.
//   pdr        pedestrian dead reckoning (SEEDS.md A, S1): steps from the accelerometer,
//              step-length model, heading from the attitude; per-particle step-length
//              scale and heading-offset states that the fixes calibrate.
//   strapdown  planar strapdown integration (SEEDS.md B.2): world acceleration drives the
//              velocity, with white acceleration noise and a velocity decay.
//   cv         constant velocity (no IMU): velocity random walk (SEEDS.md C.6).
// Noise of strapdown and cv: ParticleFilterOptions / EkfOptions::accel_noise_psd (for cv it
// is the velocity random walk's PSD) and velocity_tau_s.
#include <stdexcept>
#include <string>
#include <vector>

namespace luxloc {

enum class MotionModel { pdr, strapdown, cv };

inline std::vector<std::string> motion_model_names() { return {"pdr", "strapdown", "cv"}; }

inline std::string to_string(MotionModel m) {
  switch (m) {
    case MotionModel::pdr: return "pdr";
    case MotionModel::strapdown: return "strapdown";
    case MotionModel::cv: return "cv";
  }
  return "?";
}

// Throws std::invalid_argument for an unknown name.
inline MotionModel parse_motion_model(const std::string& name) {
  if (name == "pdr") return MotionModel::pdr;
  if (name == "strapdown") return MotionModel::strapdown;
  if (name == "cv") return MotionModel::cv;
  throw std::invalid_argument("unknown motion model '" + name + "' (valid: pdr, strapdown, cv)");
}

// Process noise of the pedestrian model beyond the per-step noise its input carries:
// the gait calibration states. Each particle (the EKF: two more state components) has a
// step-length scale k (true length = k * modelled length) and a heading offset d (walking
// direction = device heading + d). They start at k = scale0, d = 0 with the spread below and
// walk slowly, so the fixes calibrate them and dead reckoning through an outage walks
// with the calibrated gait.
struct GaitNoise {
  // Initial spread and random walk of k. 0.25 and 0.01 / sqrt(s) (were 0.10 and 0.003,
  // fitted to the simulator's one walker): over the walker population (`sim --walker
  // random`, step length 0.35-0.85 m, cadence 1.4-2.2 Hz), tuning seeds 1-10
  // (scripts/population_table.sh 1 10), the needed k spans 0.6-1.3; the narrow prior left
  // those walkers uncalibrated: blackout max 2.08 -> 0.79 m, UWB ATE 0.134 -> 0.077 m, sigma
  // consistency 70-77 % -> 83-89 %.
  double scale_sigma0 = 0.25;
  // Where k starts (the modelled length is the Weinberg model with its one K, 0.5). Over the
  // walker population the uncalibrated model runs long: the k a walker needs (`luxloc imu
  // --truth`: true distance / PDR distance) is 0.47-1.10 on tuning seeds 1-10 and 41-60,
  // mean 0.72, sd 0.16; 0.91 on the default walker, on which K was chosen. From 1.0 the
  // short-stepping walkers sat up to 2.1 prior sigma off, and dead reckoning from a known
  // start covered its error for 73.5 % of the poses on the worst (seed 56). Tuning seeds
  // 1-10 (41-60 for the pdr case), k0 = 1.0 / 0.9 / 0.8: IMU-only from the start ATE 2.19 /
  // 1.90 / 1.67 m, worst within 95 % 73.5 / 96.1 / 96.8 %; blackout 40:15 mean max in the dark
  // 0.29 / 0.28 / 0.31 m, yaw p95 1.24 / 1.31 / 1.72 deg; UWB and VLC within a few per cent
  // of each other. 0.9: every tuning walker within 1.7 sigma, the blackout kept.
  double scale0 = 0.9;
  double scale_walk = 0.01;
  double heading_offset_sigma0 = 0.05; // rad (~3 deg): initial spread of d
  double heading_offset_walk = 0.002;  // rad per sqrt(s)
  double min_scale = 0.4, max_scale = 1.5;  // 0.4: tuning seed 52 needs 0.475
  // Floor on the position diffusion (m^2/s), also while standing: model error.
  double position_psd = 1e-4;
  // Turns: a fraction of each step's turn (|omega| T) is uncertain, along and across the
  // walk: sigma per step = turn_noise |omega| T l (see GaitInput::turn_rate_rps). 0.1: the
  // walker population, seeds 1-10: sigma consistency 83 -> 86-88 %, ATE unchanged; 0.25 gave
  // 90-91 % but larger blackout excursions (the wider cloud wanders further in the dark).
  double turn_noise = 0.1;
  // The walker's own slowdown in turns, a third calibration state beside k and d: a walker
  // loses A metres of distance per radian turned, speed = k s - A r (s: the gait speed, r: the
  // angle turned, paid out with the distance, GaitInput::turn_paid_rps). A is a length: on a
  // given corner a walker slows down by the path's curvature, not by the yaw rate alone (the
  // two-thirds power law of locomotion: Vieilledent et al. 2001, Hicheur et al. 2005), so a
  // slow walker slows down more per rad/s than a fast one; per step, the loss is A times the
  // angle the step turned, whatever the pace. The particle filter carries the whole slowdown
  // (the gait model's own fixed factor is off for it; the EKF keeps 0.2 s/rad). Over the
  // walker population (`sim --walker random`; the truth's pace on straights and in turns, 1 s
  // windows, least squares) the slowdown in s/rad that walkers need is 0.10-0.39, mean 0.25,
  // sd 0.09 on tuning seeds 1-10 and 41-60, and a hold-out walker reaches 0.56 (seed 107:
  // 0.54 m/s, wide corners), 3.5 sd off a prior in s/rad; as A = c v the same walkers need
  // 0.11-0.34 m/rad, mean 0.225, sd 0.06 (seed 107: 0.30, 1.3 sd). A starts at that mean with
  // that spread and walks 0.02 m/rad per sqrt(s) (the walk the s/rad state had, tuned on
  // seeds 1-3: 0.003 collapsed before the first turn, 0.05 inflated sigma), within
  // [0, 0.7] m/rad.
  double turn_slowdown0 = 0.225;         // m/rad
  double turn_slowdown_sigma0 = 0.06;    // m/rad
  double turn_slowdown_walk = 0.02;      // m/rad per sqrt(s)
  double min_turn_slowdown = 0.0, max_turn_slowdown = 0.7;
  double min_turn_factor = 0.4;      // the speed in a turn stays above this share of k s
  // Dead reckoning (no correction for dead_reckoning_after_s): the fixes pinned k and d to
  // 1-2 % and a fraction of a degree for the stretch they saw, but the gait model's error
  // changes from one stretch to the next (turns, pace). Once per outage the particles'
  // spread of k and d is widened to at least these, so sigma grows with the distance as
  // the real error does and the next good fix is inside it. Tuning seeds 1-10 and 41-50,
  // blackout 40:15: the distance walked in the dark was off by 2-15 % (rms 6.5 %) before
  // the turn slowdown state, 0-9 % after; 0.05 (with 1.5 deg) brought the poses within
  // their 95 % ellipse during the blackout from 24-79 % to 47-100 % on the worst seeds.
  // After 1.5 s: longer than the gap between two 1 Hz fixes, so sparse fixes do not
  // re-widen what each of them pins down.
  double dead_reckoning_scale_sigma = 0.05;
  double dead_reckoning_heading_offset_sigma = 0.026;  // rad (1.5 deg)
  double dead_reckoning_after_s = 1.5;
};

}  // namespace luxloc
