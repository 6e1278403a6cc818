#include "core/sim/kidnap_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace luxloc::sim {

KidnapTrajectory::KidnapTrajectory(std::shared_ptr<const Trajectory> base, const KidnapOptions& o)
    : base_(std::move(base)), opt_(o) {
  if (!base_) throw std::invalid_argument("kidnap: no trajectory");
  if (!(o.distance_m > 0.0) || !(o.speed_mps > 0.0) || !(o.start_s >= 0.0))
    throw std::invalid_argument("kidnap: start >= 0, distance and speed > 0");
  from_ = base_->state(o.start_s);
  // The first time along the walk at least distance_m from the pick-up point (0.05 s steps).
  for (double dt = 0.05;; dt += 0.05) {
    if (dt > 3600.0)
      throw std::invalid_argument("kidnap: the walk never gets " + std::to_string(o.distance_m) +
                                  " m from where the device is picked up");
    const BodyState s = base_->state(o.start_s + dt);
    if ((s.p_BinW - from_.p_BinW).head<2>().norm() >= o.distance_m) {
      skip_s_ = dt;
      to_ = s;
      break;
    }
  }
  carry_s_ = std::max(2.0, (to_.p_BinW - from_.p_BinW).head<2>().norm() / o.speed_mps);
}

BodyState KidnapTrajectory::state(double t) const {
  if (t < opt_.start_s) return base_->state(t);
  if (t >= end_s()) {
    BodyState s = base_->state(t - carry_s_ + skip_s_);
    s.t = t;
    return s;
  }
  // Minimum jerk between the two poses: m(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5.
  const double T = carry_s_, tau = (t - opt_.start_s) / T;
  const double m = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
  const double dm = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) / T;
  const double ddm = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) / (T * T);
  BodyState s;
  s.t = t;
  const Eigen::Vector3d d = to_.p_BinW - from_.p_BinW;
  s.p_BinW = from_.p_BinW + d * m;
  s.v_BinW = d * dm;
  s.a_BinW = d * ddm;
  const double dyaw = std::remainder(to_.yaw - from_.yaw, 2.0 * std::numbers::pi);
  const double dpitch = to_.pitch - from_.pitch, droll = to_.roll - from_.roll;
  set_attitude_zyx(s, from_.yaw + dyaw * m, from_.pitch + dpitch * m, from_.roll + droll * m, dyaw * dm, dpitch * dm,
                   droll * dm);
  return s;
}

std::vector<double> KidnapTrajectory::step_times(double until_s) const {
  std::vector<double> out;
  const double shift = skip_s_ - carry_s_;  // base time = t + shift after the put-down
  for (double s : base_->step_times(std::max(opt_.start_s, until_s + shift))) {
    if (s < opt_.start_s) {
      if (s <= until_s) out.push_back(s);
    } else if (s >= opt_.start_s + skip_s_ && s - shift <= until_s) {
      out.push_back(s - shift);
    }
  }
  return out;
}

}  // namespace luxloc::sim
