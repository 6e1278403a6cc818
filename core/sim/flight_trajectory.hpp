#pragma once
// A platform that does not walk (issue 16 part 5): a drone or a ground robot follows a
// smooth closed path (SmoothPath) at a constant cruise speed (C2 start ramp, the Gait
// envelope without its steps), heading along the path, with a height profile and the
// vibration of its rotors / motors. No gait: no bounce, no heel strikes.
//   z(t)  = h0 + A sin(2 pi t / T)                                  (drone: 0.5 .. 1.7 m)
//   vibration, per axis and tone i: p = -(a_i / w_i^2) sin(w_i t + phi_i), so the
//   acceleration is a_i sin(w_i t + phi_i) exactly; the attitude gets
//   theta = (r_i / w_i) sin(...) (rate amplitude r_i). Tones of 50-300 Hz sampled by a
//   100 Hz IMU alias into 0-50 Hz, as a real rotor's do.
// Every quantity is built from Jets, so velocity, acceleration and angular rate are exact.
#include <Eigen/Core>
#include <vector>

#include "core/sim/gait.hpp"
#include "core/sim/smooth_path.hpp"
#include "core/sim/trajectory.hpp"

namespace luxloc::sim {

struct VibrationTone {
  double freq_hz = 0.0;
  double acc_mps2 = 0.0;   // linear acceleration amplitude, on every axis (phases differ)
  double rate_rps = 0.0;   // angular rate amplitude about roll and pitch
};

struct FlightOptions {
  std::vector<Eigen::Vector2d> waypoints;  // closed polygon (world x, y)
  double corner_sigma_m = 0.6;
  double start_u_m = 0.0;
  double speed_mps = 0.8;
  double start_s = 2.0;                    // at rest (hovering / parked) until then
  double ramp_s = 1.5;                     // cruise speed reached after this
  double height_m = 1.1;                   // h0
  double height_amplitude_m = 0.0;         // A
  double height_period_s = 30.0;           // T
  std::vector<VibrationTone> vibration;
};

class FlightTrajectory final : public Trajectory {
 public:
  explicit FlightTrajectory(const FlightOptions& options);
  BodyState state(double t_s) const override;
  std::vector<double> step_times(double) const override { return {}; }  // no gait

 private:
  FlightOptions opt_;
  SmoothPath path_;
  Gait envelope_;  // only its envelope and walked time: the cruise speed ramps
};

}  // namespace luxloc::sim
