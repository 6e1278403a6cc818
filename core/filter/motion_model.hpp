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
  double scale_sigma0 = 0.10;          // initial spread of k (uncalibrated Weinberg K: ~10 %)
  double scale_walk = 0.003;           // random walk of k, 1 sigma per sqrt(s)
  double heading_offset_sigma0 = 0.05; // rad (~3 deg): initial spread of d
  double heading_offset_walk = 0.002;  // rad per sqrt(s)
  double min_scale = 0.5, max_scale = 1.5;
  // Floor on the position diffusion (m^2/s), also while standing: model error.
  double position_psd = 1e-4;
};

}  // namespace luxloc
