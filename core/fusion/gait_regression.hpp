#pragma once
// The walker's step-length scale k and turn slowdown kturn by least squares on the track the
// fixes pinned down (issue 12: dead reckoning through an outage with a calibrated gait).
//
// The particles carry k and the turn slowdown A as random-walk states (core/filter/
// motion_model.hpp GaitNoise); the fixes weigh them through the positions they produced.
// Straights observe k, turns k and A together; a stretch that turns most of the time
// leaves the pair free along a line, where the random walks move the whole set: on one
// session the particles held k = 0.99-1.23 at the start of a blackout depending on the
// filter's seed, each with a spread of 0.02-0.07 (docs/MOTION.md "What is left in the
// dark"). The gait velocity is linear in k and A,
//   v = (k s - A r) u,      s the gait speed, r the turned angle it pays out (rad/s),
//                           u the walking direction,
// so over a window [t0, t1] the displacement is d = k G - A H with G = int s u dt and
// H = int r u dt. While the filter tracks (a fix in the last fix_age_s,
// position sigma below tracking_sigma_m) every window of at least window_s adds its normal
// equations with exponential forgetting (memory_s); solve() returns the ridge solution about
// the particles' own means. The fusion re-centres the particles' k and A on it once per
// outage, before the dead-reckoning widening (FusionOptions::gait_regression).
#include <Eigen/Core>
#include <optional>

#include "core/common/time.hpp"

namespace luxloc {

struct GaitRegressionOptions {
  bool enabled = true;
  // Memory of the normal equations, s. Tuning seeds (`sim --walker random`, consumer IMU,
  // blackout 40:15, seeds 1-10 and 41-50; scripts/population_table.sh CASES=blackout, calib on
  // 1-10), max error in the dark mean / worst / sessions over 0.5 m, and the calibrated PDR's
  // end error mean / worst: without 0.347 / 0.657 m / 3, 1.67 / 3.22 %; 15 s: 0.307 / 0.627 / 2;
  // 30 s: 0.301 / 0.615 / 1 (ridge 1), 0.286 / 0.566 / 1 and 1.64 / 2.60 % (ridge 0.1); 60 s:
  // 0.291 / 0.607 / 1 (ridge 1), 0.284 / 0.558 / 1 and 1.63 / 2.69 % (ridge 0.1). 30 s: a gait
  // that changes within a walk is followed sooner at no cost on these.
  double memory_s = 30.0;
  // Weight of the particles' own (a, c) as a prior, in units of G.G (m^2: one second's window
  // at 1 m/s weighs ~1): 0.1, see memory_s.
  double ridge = 0.1;
  // The prior of the window-rejection fit (before the particles' means are asked): the gait
  // a walker starts with (the fusion sets GaitNoise::scale0, turn_slowdown0).
  double reject_prior_scale = 0.9, reject_prior_turn_slowdown = 0.225;
  double window_s = 1.0;          // the shortest window: fixes' noise / displacement small
  // Windows the fit needs before solve() answers (and before a window can be rejected as
  // off the fit). A walk's first seconds are a few windows of a ramping gait: on a drawn
  // world with sparse lights (`sim --world random`, tuning seed 7) the first outage came
  // 4.6 s into the walk, 2 windows fitted k = 1.24 against the 1.01 the walker needs, and
  // the particles (0.97 +- 0.11, nearer the truth) were shifted onto it: 0.55 m off after
  // 2 s in the dark. 5: the count the rejection test always waited for.
  int min_windows = 5;
  double fix_age_s = 0.2;         // "tracking": a fix this recent ...
  double tracking_sigma_m = 0.1;  // ... and the position's largest sigma below this
  // A window whose displacement misses the current solution by more than this is not added
  // (a re-initialisation, a kidnap, a fix the filter jumped to).
  double max_residual_m = 0.3;
};

class GaitRegression {
 public:
  explicit GaitRegression(const GaitRegressionOptions& options = {}) : options_(options) {}
  // The gait's motion over dt: gait speed s (m/s), the turned angle paid out with it (rad/s,
  // GaitSpeed::turn_paid_rps), walking direction u (unit vector in the world). Non-finite
  // inputs are ignored.
  void add_motion(double speed_mps, double turn_rps, const Eigen::Vector2d& u, double dt);
  // The filter's position after the prediction to t, and whether it is tracking (see
  // GaitRegressionOptions); closes a window when one is due.
  void add_position(TimeNs t, const Eigen::Vector2d& p, bool tracking);
  struct Solution {
    double scale = 1.0;                   // k
    double turn_slowdown_m_per_rad = 0.0;  // A
    int windows = 0;                      // windows in the memory (not discounted)
  };
  // The ridge solution about the prior (the particles' means); empty before min_windows.
  std::optional<Solution> solve(double prior_scale, double prior_turn_slowdown_m_per_rad) const;
  int windows() const { return windows_; }
  int rejected_windows() const { return rejected_; }
  void reset();

 private:
  // (k, A), the ridge solution about the prior; empty before the first window.
  std::optional<Eigen::Vector2d> fit(double prior_scale, double prior_turn_slowdown_m_per_rad) const;
  GaitRegressionOptions options_;
  Eigen::Vector2d g_ = Eigen::Vector2d::Zero(), h_ = Eigen::Vector2d::Zero(), anchor_ = Eigen::Vector2d::Zero();
  std::optional<TimeNs> t_anchor_;
  Eigen::Matrix2d A_ = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b_ = Eigen::Vector2d::Zero();
  int windows_ = 0, rejected_ = 0;
};

}  // namespace luxloc
