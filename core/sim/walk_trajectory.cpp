#include "core/sim/walk_trajectory.hpp"

#include <cmath>
#include <numbers>

namespace luxloc::sim {

WalkTrajectory::WalkTrajectory(const WalkOptions& options)
    : opt_(options), path_(options.waypoints, options.corner_sigma_m), gait_(options.walking, options.gait) {}

// u' = V g (1 + m cos phi) with phi' = 2 pi f g integrates in closed form:
// u = u0 + V G + V m sin(phi) / (2 pi f).
Jet WalkTrajectory::path_parameter(double t_s) const {
  const GaitOptions& g = opt_.gait;
  const Jet phi = gait_.step_phase(t_s);
  return opt_.start_u_m + g.speed_mps * gait_.walked_time(t_s) +
         (g.speed_mps * g.speed_modulation / (2.0 * std::numbers::pi * g.step_hz)) * sin(phi);
}

// GaitOptions::heel_impact_mps2: -A w^2 e(tau) with e = exp(-tau^2 / (2 w^2)), tau = t - t_k;
// its derivatives A tau e and A (1 - tau^2 / w^2) e (+A at the strike, zero net velocity).
// Beyond 6 w the spike is below 1e-7 A. The amplitude follows the envelope squared at the
// strike, so the small steps of a start or stop ramp land softly.
Jet WalkTrajectory::heel_impact(double t_s) const {
  const GaitOptions& g = opt_.gait;
  const double w = g.heel_impact_width_s;
  const std::optional<double> tk = gait_.heel_strike_near(t_s, 6.0 * w);
  if (!tk) return Jet::constant(0.0);
  const double env = gait_.envelope(*tk).v;
  const double a = g.heel_impact_mps2 * env * env, tau = t_s - *tk;
  const double e = std::exp(-0.5 * tau * tau / (w * w));
  return {-a * w * w * e, a * tau * e, a * (1.0 - tau * tau / (w * w)) * e};
}

BodyState WalkTrajectory::state(double t_s) const {
  const GaitOptions& g = opt_.gait;
  const Jet u = path_parameter(t_s);
  const PathPoint pp = path_.at(u.v);
  // Chain rule through the path: c(u(t))' = c1 u', c(u(t))'' = c2 u'^2 + c1 u''.
  auto along = [&u](double f0, double f1, double f2) { return Jet{f0, f1 * u.d, f2 * u.d * u.d + f1 * u.dd}; };
  const Jet x = along(pp.c.x(), pp.c1.x(), pp.c2.x());
  const Jet y = along(pp.c.y(), pp.c1.y(), pp.c2.y());
  // Heading of the path tangent (defined while standing too, unlike the velocity's).
  const Jet heading = atan2(along(pp.c1.y(), pp.c2.y(), pp.c3.y()), along(pp.c1.x(), pp.c2.x(), pp.c3.x()));

  const Jet env = gait_.envelope(t_s);
  const Jet phi = gait_.step_phase(t_s);
  const Jet half = 0.5 * phi;  // stride phase: sways alternate left / right every step
  Jet z = opt_.height_m - g.bounce_m * (env * cos(phi));
  if (g.heel_impact_mps2 > 0.0) z = z + heel_impact(t_s);
  const Jet roll = g.roll_sway_rad * (env * sin(half));
  const Jet pitch = g.pitch_sway_rad * (env * sin(phi));
  const Jet yaw = heading + g.yaw_sway_rad * (env * cos(half));

  BodyState s;
  s.t = t_s;
  s.p_BinW = {x.v, y.v, z.v};
  s.v_BinW = {x.d, y.d, z.d};
  s.a_BinW = {x.dd, y.dd, z.dd};
  set_attitude_zyx(s, yaw.v, pitch.v, roll.v, yaw.d, pitch.d, roll.d);
  return s;
}

}  // namespace luxloc::sim
