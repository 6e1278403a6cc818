#include "core/imu/gravity_window.hpp"

namespace luxloc {

GravityWindow::GravityWindow(const GravityWindowOptions& options) : options_(options) {}

void GravityWindow::add(TimeNs t, const Eigen::Vector3d& acc_inB) {
  if (!acc_inB.allFinite()) return;
  if (!samples_.empty() && t <= samples_.back().first) return;
  samples_.emplace_back(t, acc_inB);
  sum_ += acc_inB;
  const TimeNs width = seconds_to_ns(options_.window_s);
  while (samples_.size() > 1 && t - samples_.front().first > width) {
    sum_ -= samples_.front().second;
    samples_.pop_front();
  }
  // A running sum drifts by rounding over hours of samples: recompute it when the window
  // has turned over many times (cheap: a few hundred samples).
  if (++adds_ % 65536 == 0) {
    sum_.setZero();
    for (const auto& [ts, a] : samples_) sum_ += a;
  }
}

Eigen::Vector3d GravityWindow::up_inB() const {
  const double n = sum_.norm();
  return n > 0.0 ? Eigen::Vector3d(sum_ / n) : Eigen::Vector3d::Zero();
}

}  // namespace luxloc
