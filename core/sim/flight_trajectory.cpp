#include "core/sim/flight_trajectory.hpp"

#include <limits>
#include <numbers>

namespace luxloc::sim {
namespace {

GaitOptions cruise(const FlightOptions& o) {
  GaitOptions g;
  g.speed_mps = o.speed_mps;
  g.ramp_s = o.ramp_s;
  g.speed_modulation = 0.0;
  g.bounce_m = 0.0;
  g.roll_sway_rad = g.pitch_sway_rad = g.yaw_sway_rad = 0.0;
  return g;
}

// Sum of the tones on one axis; `axis` shifts the phases so the axes are not in step.
Jet vibration(const std::vector<VibrationTone>& tones, double t, int axis, bool angular) {
  Jet sum;
  for (std::size_t i = 0; i < tones.size(); ++i) {
    const double w = 2.0 * std::numbers::pi * tones[i].freq_hz;
    const double phase = 1.3 * static_cast<double>(axis) + 0.7 * static_cast<double>(i);
    const Jet arg{w * t + phase, w, 0.0};
    sum = sum + (angular ? tones[i].rate_rps / w : -tones[i].acc_mps2 / (w * w)) * sin(arg);
  }
  return sum;
}

}  // namespace

FlightTrajectory::FlightTrajectory(const FlightOptions& options)
    : opt_(options),
      path_(options.waypoints, options.corner_sigma_m),
      envelope_({{options.start_s, std::numeric_limits<double>::infinity()}}, cruise(options)) {}

BodyState FlightTrajectory::state(double t_s) const {
  const Jet u = opt_.start_u_m + opt_.speed_mps * envelope_.walked_time(t_s);
  const PathPoint pp = path_.at(u.v);
  auto along = [&u](double f0, double f1, double f2) { return Jet{f0, f1 * u.d, f2 * u.d * u.d + f1 * u.dd}; };
  const Jet x = along(pp.c.x(), pp.c1.x(), pp.c2.x()) + vibration(opt_.vibration, t_s, 0, false);
  const Jet y = along(pp.c.y(), pp.c1.y(), pp.c2.y()) + vibration(opt_.vibration, t_s, 1, false);
  const double w = 2.0 * std::numbers::pi / opt_.height_period_s;
  const Jet z = opt_.height_m + opt_.height_amplitude_m * sin(Jet{w * t_s, w, 0.0}) +
                vibration(opt_.vibration, t_s, 2, false);
  const Jet heading = atan2(along(pp.c1.y(), pp.c2.y(), pp.c3.y()), along(pp.c1.x(), pp.c2.x(), pp.c3.x()));
  const Jet roll = vibration(opt_.vibration, t_s, 3, true);
  const Jet pitch = vibration(opt_.vibration, t_s, 4, true);
  BodyState s;
  s.t = t_s;
  s.p_BinW = {x.v, y.v, z.v};
  s.v_BinW = {x.d, y.d, z.d};
  s.a_BinW = {x.dd, y.dd, z.dd};
  set_attitude_zyx(s, heading.v, pitch.v, roll.v, heading.d, pitch.d, roll.d);
  return s;
}

}  // namespace luxloc::sim
