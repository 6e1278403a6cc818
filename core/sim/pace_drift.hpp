#pragma once
// A walker's pace drifting within a session (issue 12 part 1: "cadence drawn per session
// (and drifting within it), speed changes"). The speed factor q is a smooth function of the
// walked time G (core/sim/gait.hpp), a sum of slow sine waves:
//   q(G) = 1 + sum_i a_i sin(2 pi G / T_i + psi_i),
// split between the cadence and the step length at a constant walk ratio (step length over
// cadence stays nearly constant across a person's speeds, Sekiya & Nagasaki 1998):
//   c(G) = q^(1/2) (cadence factor), l(G) = q^(1/2) (step-length factor).
// Functions of G, not of t, so that the pace holds still while the walker stands and the
// walk stays C2 through the stops' ramps.
//
// The step count N(G) = f0 int_0^G c and the walked distance D(G) = int_0^G l c (1 + m cos 2 pi N)
// (in nominal-speed seconds: speed_mps x D is metres along the path) have no closed form.
// They are tabulated at every kPanel of G by 8-point Gauss-Legendre quadrature and finished
// from the nearest node by the same rule, so each is exact to ~1e-12 and their derivatives
// (c, l c (1 + m cos 2 pi N)) are exact by construction: the IMU stays the truth's.
#include <vector>

#include "core/sim/jet.hpp"

namespace luxloc::sim {

struct PaceWave {
  double amplitude = 0.0;  // a_i, fraction of the nominal speed
  double period_s = 60.0;  // T_i, walked seconds
  double phase_rad = 0.0;  // psi_i
};

// A short slowdown (a few side steps, core/sim/walk_trajectory.hpp): q is multiplied by
// 1 - depth P(G), P a plateau with C2 smoothstep edges of ramp_s, over [start_s, start_s + duration_s]
// of walked time.
struct PaceDip {
  double start_s = 0.0;     // walked seconds
  double duration_s = 2.0;  // including both ramps
  double ramp_s = 0.5;
  double depth = 0.5;  // fraction of the speed lost on the plateau, < 1
};

class PaceDrift {
 public:
  // Table spacing in walked seconds: a fifth of the fastest step (2.2 Hz, +-25 % drift) at most
  // 1.7 rad of step phase per panel, where 8-point Gauss-Legendre is exact to ~1e-13. A dip's
  // edges lie on panel boundaries (Gait rounds them), so every panel integrates a polynomial
  // of smoothstep pieces, never across a knot.
  static constexpr double kPanel = 0.1;

  // `waves`: sum of |a_i| < 0.5 (the pace never halves); periods >= 5 s (slower than steps).
  // f0: nominal cadence (Hz); m: the per-step speed modulation (GaitOptions); horizon_s:
  // the walked time the tables cover; `dips`: slowdowns, each 0 <= depth < 1 and at least
  // two ramps long. Throws std::invalid_argument.
  PaceDrift(std::vector<PaceWave> waves, double f0, double m, double horizon_s, std::vector<PaceDip> dips = {});

  Jet speed_factor(double G) const;    // q and its derivatives in G
  Jet cadence_factor(double G) const;  // c = sqrt q
  Jet length_factor(double G) const;   // l = sqrt q
  double steps(double G) const;        // N(G) = f0 int_0^G c
  Jet distance(double G) const;        // D(G), dD/dG, d2D/dG2
  double horizon_s() const { return horizon_; }
  const std::vector<PaceWave>& waves() const { return waves_; }

 private:
  double distance_rate(double G) const;  // l c (1 + m cos 2 pi N(G))
  std::vector<PaceWave> waves_;
  std::vector<PaceDip> dips_;
  double f0_ = 1.0, m_ = 0.0, horizon_ = 0.0;
  std::vector<double> steps_at_;     // N at k kPanel
  std::vector<double> distance_at_;  // D at k kPanel
};

}  // namespace luxloc::sim
