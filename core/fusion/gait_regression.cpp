#include "core/fusion/gait_regression.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace luxloc {

void GaitRegression::add_motion(double speed_mps, double turn_rps, const Eigen::Vector2d& u, double dt) {
  if (!std::isfinite(speed_mps) || !std::isfinite(turn_rps) || !u.allFinite() || !(dt > 0.0) || !std::isfinite(dt))
    return;
  g_ += speed_mps * dt * u;
  h_ += std::abs(turn_rps) * dt * u;
}

void GaitRegression::add_position(TimeNs t, const Eigen::Vector2d& p, bool tracking) {
  if (!options_.enabled) return;
  const auto restart = [&] {
    anchor_ = p;
    t_anchor_ = t;
    g_.setZero();
    h_.setZero();
  };
  if (!tracking || !p.allFinite()) {
    t_anchor_.reset();  // the window needs both ends pinned by fixes
    return;
  }
  if (!t_anchor_) return restart();
  const double span = ns_to_seconds(t - *t_anchor_);
  if (span < options_.window_s) return;
  const Eigen::Vector2d d = p - anchor_;
  // A window far off the current solution is a jump of the filter, not the gait.
  if (const std::optional<Eigen::Vector2d> x = fit(options_.reject_prior_scale, options_.reject_prior_turn_slowdown); x && windows_ >= options_.min_windows) {
    const Eigen::Vector2d r = d - (x->x() * g_ - x->y() * h_);
    if (r.norm() > options_.max_residual_m) {
      ++rejected_;
      return restart();
    }
  }
  // d = k G - A H: the row of the design for the unknowns (k, A) is [G, -H] per axis.
  Eigen::Matrix2d M;
  M << g_.dot(g_), -g_.dot(h_), -g_.dot(h_), h_.dot(h_);
  const double f = std::exp(-span / options_.memory_s);
  A_ = f * A_ + M;
  b_ = f * b_ + Eigen::Vector2d(g_.dot(d), -h_.dot(d));
  ++windows_;
  restart();
}

std::optional<Eigen::Vector2d> GaitRegression::fit(double prior_scale, double prior_turn_slowdown_m_per_rad) const {
  if (!options_.enabled || windows_ == 0 || !std::isfinite(prior_scale) || !std::isfinite(prior_turn_slowdown_m_per_rad))
    return std::nullopt;
  const Eigen::Vector2d prior(prior_scale, prior_turn_slowdown_m_per_rad);
  const Eigen::Matrix2d A = A_ + options_.ridge * Eigen::Matrix2d::Identity();
  const Eigen::Vector2d x = A.ldlt().solve(b_ + options_.ridge * prior);
  if (!x.allFinite() || !(x.x() > 0.1)) return std::nullopt;
  return x;
}

std::optional<GaitRegression::Solution> GaitRegression::solve(double prior_scale,
                                                              double prior_turn_slowdown_m_per_rad) const {
  if (windows_ < options_.min_windows) return std::nullopt;
  const std::optional<Eigen::Vector2d> x = fit(prior_scale, prior_turn_slowdown_m_per_rad);
  if (!x) return std::nullopt;
  return Solution{x->x(), x->y(), windows_};
}

void GaitRegression::reset() {
  t_anchor_.reset();
  g_.setZero();
  h_.setZero();
  A_.setZero();
  b_.setZero();
  windows_ = rejected_ = 0;
}

}  // namespace luxloc
