#pragma once
// When and how a pedestrian walks: a smooth walking envelope g(t) in [0, 1] (0 standing,
// 1 walking at the nominal speed) made of walking intervals with C2 ramps, its integral
// G(t) ("walking time"), and the step phase phi = 2 pi f_step G(t). Heel strikes happen at
// phi = 2 pi k, so the cadence slows with the envelope and freezes during stops.
#include <memory>
#include <optional>
#include <vector>

#include "core/sim/jet.hpp"
#include "core/sim/pace_drift.hpp"

namespace luxloc::sim {

struct WalkInterval {
  double start_s = 0.0;  // envelope starts rising
  double stop_s = 0.0;   // envelope is back at 0 (may be +infinity: walk to the end)
};

struct GaitOptions {
  double speed_mps = 1.25;         // along-path speed on straights at envelope 1
  double step_hz = 1.8;            // cadence (steps per second)
  double ramp_s = 1.0;             // start / stop ramp duration
  double speed_modulation = 0.10;  // forward speed oscillates +-10 % per step (fastest at heel strike)
  double bounce_m = 0.015;         // vertical oscillation amplitude (3 cm peak to peak), lowest at heel strike
  double roll_sway_rad = 0.044;    // 2.5 deg, side-to-side at the stride frequency (step_hz / 2)
  double pitch_sway_rad = 0.035;   // 2.0 deg at the step frequency
  double yaw_sway_rad = 0.017;     // 1.0 deg at the stride frequency
  double min_step_envelope = 0.5;  // heel strikes where g(t) < this are not counted as steps
  // Heel-strike impact (issue 12: "fast walking (1.7 m/s, 12 g peaks)"): a device on the leg,
  // in a trouser pocket or on the hip sees each heel strike as a short spike of vertical
  // acceleration, several g high. Modelled as z -= A w^2 g(t_k)^2 exp(-(t - t_k)^2 / (2 w^2))
  // at every heel strike t_k: the acceleration then peaks at +A at the strike with negative
  // lobes of -0.45 A either side, and the velocity and position come back after the spike
  // (a 1-2 cm dip), so the truth and the IMU stay consistent. 0 = none (every scenario).
  double heel_impact_mps2 = 0.0;
  // w: 12 ms, a spike of ~50 ms base, within the 10-50 ms of measured shank and hip impacts.
  double heel_impact_width_s = 0.012;
  // The pace drifting within the session (core/sim/pace_drift.hpp): the speed factor's slow
  // waves in walked time; none when empty (every scenario; `--walker random` draws them).
  std::vector<PaceWave> pace_waves;
  // Slowdowns in walked time (side steps: WalkOptions::side_steps fills them), edges on
  // multiples of PaceDrift::kPanel.
  std::vector<PaceDip> pace_dips;
  double pace_horizon_s = 3600.0;  // walked time the drift's tables cover
};

class Gait {
 public:
  // Intervals sorted, non-overlapping, each at least 2 ramps long; throws std::invalid_argument.
  Gait(std::vector<WalkInterval> walking, const GaitOptions& options);

  Jet envelope(double t) const;      // g, g', g''
  Jet walked_time(double t) const;   // G = integral of g, with G' = g and G'' = g'
  Jet step_count(double t) const;    // N = step_hz G, or step_hz int_0^G c with a drift
  Jet step_phase(double t) const;    // phi = 2 pi N (radians)
  // The walked distance in nominal-speed seconds, D = int (1 + m cos phi) dG (with a drift
  // int q (1 + m cos phi) dG), as a function of the walked time G: D, dD/dG, d2D/dG2.
  Jet distance_in_walked_time(double G) const;
  // The step-length factor l (1 without a drift) at time t, with its time derivatives.
  Jet length_factor(double t) const;
  bool drifts() const { return drift_ != nullptr; }
  std::vector<double> heel_strikes(double until_s) const;
  // The heel strike nearest to t within +-window_s (any envelope), if one is.
  std::optional<double> heel_strike_near(double t, double window_s) const;
  const GaitOptions& options() const { return opt_; }

 private:
  std::vector<WalkInterval> walking_;
  GaitOptions opt_;
  std::shared_ptr<const PaceDrift> drift_;  // shared: the tables are immutable
};

}  // namespace luxloc::sim
