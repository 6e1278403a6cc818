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
// direction = device heading + d). They start at k = 1, d = 0 with the spread below and
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
  double scale_walk = 0.01;
  double heading_offset_sigma0 = 0.05; // rad (~3 deg): initial spread of d
  double heading_offset_walk = 0.002;  // rad per sqrt(s)
  double min_scale = 0.5, max_scale = 1.5;
  // Floor on the position diffusion (m^2/s), also while standing: model error.
  double position_psd = 1e-4;
  // Turns: a fraction of each step's turn (|omega| T) is uncertain, along and across the
  // walk: sigma per step = turn_noise |omega| T l (see GaitInput::turn_rate_rps). 0.1: the
  // walker population, seeds 1-10: sigma consistency 83 -> 86-88 %, ATE unchanged; 0.25 gave
  // 90-91 % but larger blackout excursions (the wider cloud wanders further in the dark).
  double turn_noise = 0.1;
};

}  // namespace luxloc
