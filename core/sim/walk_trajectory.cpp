#include "core/sim/walk_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <stdexcept>

namespace luxloc::sim {
namespace {

double round_to_panel(double x) { return std::round(x / PaceDrift::kPanel) * PaceDrift::kPanel; }

// The side steps in walked time: edges on panel boundaries (PaceDrift::kPanel), so the pace
// tables never integrate across a knot of the dips' smoothsteps. Throws for a side step
// outside a walk's plateau.
std::vector<PaceDip> plan_side_steps(const WalkOptions& o) {
  std::vector<PaceDip> dips;
  if (o.side_steps.empty()) return dips;
  GaitOptions plain = o.gait;  // the envelope alone decides G(t)
  plain.pace_waves.clear();
  plain.pace_dips.clear();
  const Gait envelope(o.walking, plain);
  const double T = o.gait.ramp_s;
  double prev_end = -std::numeric_limits<double>::infinity();
  for (const SideStep& side : o.side_steps) {
    const double end = side.start_s + side.duration_s;
    bool inside = false;
    for (const WalkInterval& w : o.walking) inside = inside || (side.start_s >= w.start_s + T && end <= w.stop_s - T);
    if (!inside || !(side.start_s >= prev_end) || !(side.ramp_s > 0.0) || !(side.duration_s >= 2.0 * side.ramp_s) ||
        !(side.slowdown >= 0.0 && side.slowdown < 1.0))
      throw std::invalid_argument("WalkTrajectory: side steps must be sorted, apart, within a walk's plateau, "
                                  "at least two turns long, slowing by less than the whole speed");
    PaceDip d;
    d.start_s = round_to_panel(envelope.walked_time(side.start_s).v);
    d.ramp_s = std::max(PaceDrift::kPanel, round_to_panel(side.ramp_s));
    d.duration_s = std::max(2.0 * d.ramp_s, round_to_panel(side.duration_s));
    d.depth = side.slowdown;
    dips.push_back(d);
    prev_end = end;
  }
  return dips;
}

GaitOptions with_side_steps(const WalkOptions& o, const std::vector<PaceDip>& dips) {
  GaitOptions g = o.gait;
  g.pace_dips.insert(g.pace_dips.end(), dips.begin(), dips.end());
  return g;
}

}  // namespace

WalkTrajectory::WalkTrajectory(const WalkOptions& options)
    : WalkTrajectory(options, plan_side_steps(options)) {}

WalkTrajectory::WalkTrajectory(const WalkOptions& options, std::vector<PaceDip> side_steps_G)
    : opt_(options),
      path_(options.waypoints, options.corner_sigma_m),
      gait_(options.walking, with_side_steps(options, side_steps_G)),
      side_steps_G_(std::move(side_steps_G)) {
  double prev_end = -std::numeric_limits<double>::infinity(), distance = 0.0, prev_D = 0.0, sign = 1.0;
  for (const TurnOnSpot& turn : opt_.turns) {
    const double end = turn.start_s + turn.duration_s;
    if (!(turn.duration_s > 0.0) || !(turn.start_s >= prev_end) || !std::isfinite(end))
      throw std::invalid_argument("WalkTrajectory: turns must be sorted, apart and of positive duration");
    for (const WalkInterval& w : opt_.walking)
      if (turn.start_s < w.stop_s && end > w.start_s)
        throw std::invalid_argument("WalkTrajectory: a turn on the spot must lie within a standing time");
    // D is a function of G alone (D(0) = 0); the walk since the previous turn counts with its sign.
    const double D_k = gait_.distance_in_walked_time(gait_.walked_time(turn.start_s).v).v;
    distance += sign * (D_k - prev_D);
    prev_D = D_k;
    sign = -sign;
    turn_offset_s_.push_back(distance - sign * D_k);
    prev_end = end;
  }
}

// u' = V g (1 + m cos phi) with phi' = 2 pi f g integrates in closed form:
// u = u0 + V G + V m sin(phi) / (2 pi f).
// With a drift or turns: u = u0 + V (A_k + (-1)^k (D(G) - D(G_k))) after k turns, where D(G)
// is the walked distance (Gait::distance_in_walked_time) and A_k the signed distance before
// turn k. The sign flips while standing (G' = G'' = 0), so u stays C2.
Jet WalkTrajectory::path_parameter(double t_s) const {
  const GaitOptions& g = opt_.gait;
  if (!gait_.drifts() && opt_.turns.empty()) {
    const Jet phi = gait_.step_phase(t_s);
    return opt_.start_u_m + g.speed_mps * gait_.walked_time(t_s) +
           (g.speed_mps * g.speed_modulation / (2.0 * std::numbers::pi * g.step_hz)) * sin(phi);
  }
  const Jet G = gait_.walked_time(t_s);
  const Jet Dt = compose(gait_.distance_in_walked_time(G.v), G);
  std::size_t k = 0;
  while (k < opt_.turns.size() && opt_.turns[k].start_s <= t_s) ++k;
  if (k == 0) return opt_.start_u_m + g.speed_mps * Dt;
  const double sign = k % 2 == 0 ? 1.0 : -1.0;
  return opt_.start_u_m + g.speed_mps * turn_offset_s_[k - 1] + (g.speed_mps * sign) * Dt;
}

Jet WalkTrajectory::turned_yaw(double t_s) const {
  Jet yaw = Jet::constant(0.0);
  for (const TurnOnSpot& turn : opt_.turns)
    yaw = yaw + (turn.left ? std::numbers::pi : -std::numbers::pi) * smoothstep(t_s, turn.start_s, turn.duration_s);
  return yaw;
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

// Each side step's plateau P(G) (smoothstep edges in walked time) turns the body by -+pi/2
// against the path; composed with G(t) by the chain rule (G' = 1, G'' = 0 on a walk's plateau,
// where side steps lie, but exact anywhere).
Jet WalkTrajectory::side_step_yaw(double t_s) const {
  if (side_steps_G_.empty()) return Jet::constant(0.0);
  const Jet G = gait_.walked_time(t_s);
  Jet yaw = Jet::constant(0.0);
  for (std::size_t i = 0; i < side_steps_G_.size(); ++i) {
    const PaceDip& d = side_steps_G_[i];
    const double turn = opt_.side_steps[i].left ? -0.5 * std::numbers::pi : 0.5 * std::numbers::pi;
    yaw = yaw + turn * compose(plateau(G.v, d.start_s, d.duration_s, d.ramp_s), G);
  }
  return yaw;
}

BodyState WalkTrajectory::state(double t_s) const {
  const GaitOptions& g = opt_.gait;
  const Jet u = path_parameter(t_s);
  const PathPoint pp = path_.at(u.v);
  // Chain rule through the path: c(u(t))' = c1 u', c(u(t))'' = c2 u'^2 + c1 u''.
  auto along = [&u](double f0, double f1, double f2) { return Jet{f0, f1 * u.d, f2 * u.d * u.d + f1 * u.dd}; };
  Jet x = along(pp.c.x(), pp.c1.x(), pp.c2.x());
  Jet y = along(pp.c.y(), pp.c1.y(), pp.c2.y());
  // Heading of the path tangent (defined while standing too, unlike the velocity's).
  const Jet heading = atan2(along(pp.c1.y(), pp.c2.y(), pp.c3.y()), along(pp.c1.x(), pp.c2.x(), pp.c3.x()));

  const Jet env = gait_.envelope(t_s);
  const Jet phi = gait_.step_phase(t_s);
  const Jet half = 0.5 * phi;  // stride phase: sways alternate left / right every step
  Jet z = gait_.drifts() ? opt_.height_m - g.bounce_m * (gait_.length_factor(t_s) * env * cos(phi))
                         : opt_.height_m - g.bounce_m * (env * cos(phi));
  if (g.heel_impact_mps2 > 0.0) z = z + heel_impact(t_s);
  const Jet roll = g.roll_sway_rad * (env * sin(half));
  const Jet pitch = g.pitch_sway_rad * (env * sin(phi));
  Jet yaw = heading + g.yaw_sway_rad * (env * cos(half));
  if (!opt_.turns.empty()) yaw = yaw + turned_yaw(t_s);
  if (!side_steps_G_.empty()) yaw = yaw + side_step_yaw(t_s);
  // The device off the turning axis: p = p_axis + Rz(yaw) l (the lever turns with the body's
  // yaw, sway included; roll and pitch sway turn the device about its own centre).
  if (opt_.lever_arm_m.squaredNorm() > 0.0) {
    const Jet c = cos(yaw), s = sin(yaw);
    const double f = opt_.lever_arm_m.x(), l = opt_.lever_arm_m.y();
    x = x + (f * c - l * s);
    y = y + (f * s + l * c);
  }

  BodyState s;
  s.t = t_s;
  s.p_BinW = {x.v, y.v, z.v};
  s.v_BinW = {x.d, y.d, z.d};
  s.a_BinW = {x.dd, y.dd, z.dd};
  set_attitude_zyx(s, yaw.v, pitch.v, roll.v, yaw.d, pitch.d, roll.d);
  return s;
}

}  // namespace luxloc::sim
