#include "core/sim/gait.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace luxloc::sim {
namespace {

// The ramps are the quintic smoothstep S (jet.hpp: S' and S'' vanish at both ends, so the
// envelope, and with it the speed and acceleration, is C2); their integral int_0^x S:
double intS(double x) { return x * x * x * x * (2.5 + x * (-3.0 + x)); }

}  // namespace

Gait::Gait(std::vector<WalkInterval> walking, const GaitOptions& options)
    : walking_(std::move(walking)), opt_(options) {
  if (!(opt_.ramp_s > 0.0) || !(opt_.step_hz > 0.0) || !(opt_.speed_mps >= 0.0) ||
      !(std::abs(opt_.speed_modulation) < 1.0))
    throw std::invalid_argument("Gait: invalid options");
  double prev_stop = -std::numeric_limits<double>::infinity();
  for (const WalkInterval& w : walking_) {
    if (!(w.start_s >= prev_stop) || !(w.stop_s - w.start_s >= 2.0 * opt_.ramp_s))
      throw std::invalid_argument("Gait: walking intervals overlap or are shorter than two ramps");
    prev_stop = w.stop_s;
  }
  if (!opt_.pace_waves.empty() || !opt_.pace_dips.empty())
    drift_ = std::make_shared<const PaceDrift>(opt_.pace_waves, opt_.step_hz, opt_.speed_modulation,
                                               opt_.pace_horizon_s, opt_.pace_dips);
}

Jet Gait::envelope(double t) const {
  const double T = opt_.ramp_s;
  for (const WalkInterval& w : walking_) {
    if (t <= w.start_s || t >= w.stop_s) continue;
    if (t < w.start_s + T) return smoothstep(t, w.start_s, T);
    if (t <= w.stop_s - T) return Jet::constant(1.0);
    return 1.0 - smoothstep(t, w.stop_s - T, T);
  }
  return Jet::constant(0.0);
}

Jet Gait::walked_time(double t) const {
  const double T = opt_.ramp_s;
  double G = 0.0;
  for (const WalkInterval& w : walking_) {
    if (t <= w.start_s) break;
    G += T * intS(std::min((t - w.start_s) / T, 1.0));
    const double plateau_end = w.stop_s - T;  // +inf for an open interval
    G += std::max(0.0, std::min(t, plateau_end) - (w.start_s + T));
    if (t > plateau_end) {
      const double y = std::min((t - plateau_end) / T, 1.0);
      G += T * (y - intS(y));
    }
  }
  const Jet g = envelope(t);
  return {G, g.v, g.d};
}

Jet Gait::step_count(double t) const {
  const Jet G = walked_time(t);
  if (!drift_) return opt_.step_hz * G;
  const Jet c = drift_->cadence_factor(G.v);
  return opt_.step_hz * compose({drift_->steps(G.v) / opt_.step_hz, c.v, c.d}, G);
}

Jet Gait::step_phase(double t) const {
  if (!drift_) return 2.0 * std::numbers::pi * opt_.step_hz * walked_time(t);  // bit for bit as before drifts
  return 2.0 * std::numbers::pi * step_count(t);
}

Jet Gait::distance_in_walked_time(double G) const {
  if (drift_) return drift_->distance(G);
  const double k = 2.0 * std::numbers::pi * opt_.step_hz, m = opt_.speed_modulation;
  return {G + m * std::sin(k * G) / k, 1.0 + m * std::cos(k * G), -m * k * std::sin(k * G)};
}

Jet Gait::length_factor(double t) const {
  if (!drift_) return Jet::constant(1.0);
  const Jet G = walked_time(t);
  return compose(drift_->length_factor(G.v), G);
}

std::optional<double> Gait::heel_strike_near(double t, double window_s) const {
  // f G(t) is non-decreasing: a strike (f G = k, k >= 1) lies in [t - w, t + w] when an
  // integer lies in (f G(t - w), f G(t + w)]; bisection finds its first time.
  const double s0 = step_count(t - window_s).v, s1 = step_count(t + window_s).v;
  const double k = std::floor(s1);
  if (!(k > s0) || k < 1.0) return std::nullopt;
  // To the last bit: the same strike time whatever the window (a jitter of 1 ns would move
  // the impact's velocity by ~1e-9 m and show in finite differences of the truth).
  double lo = t - window_s, hi = t + window_s;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (step_count(mid).v >= k ? hi : lo) = mid;
  }
  return hi;
}

std::vector<double> Gait::heel_strikes(double until_s) const {
  std::vector<double> out;
  const double steps_total = step_count(until_s).v;
  for (int k = 1; k <= static_cast<int>(std::floor(steps_total)); ++k) {
    // First time with f G(t) >= k (G is non-decreasing): bisection to ~1e-9 s.
    double lo = 0.0, hi = until_s;
    for (int it = 0; it < 64 && hi - lo > 1e-10; ++it) {
      const double mid = 0.5 * (lo + hi);
      (step_count(mid).v >= k ? hi : lo) = mid;
    }
    if (envelope(hi).v >= opt_.min_step_envelope) out.push_back(hi);
  }
  return out;
}

}  // namespace luxloc::sim
