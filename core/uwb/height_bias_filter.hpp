#pragma once
// The UWB nuisance states the planar filters do not carry (issue 16 parts 1-3): the device
// height z and one slow range bias per anchor, estimated while running by an extended
// Kalman filter over the ranges alone (docs/PLATFORMS.md "Online bias and height"):
//   state     x = [p (3-D), v (3-D), b_1, (s_1), .. b_m, (s_m)]  (an anchor's b, and its
//             scale error s when estimated, join when it is first heard)
//   motion    p' = v, v white acceleration (psd q_xy horizontally, q_z vertically);
//             b_k, s_k slow random walks (psd q_b, q_s)
//   range     r_k = (1 + s_k) || p - a_k || + b_k + n,   n ~ N(0, s_r^2)
// The scale separates from the bias only through the spread of distances an anchor is heard
// at (a drone's 2-9 m): its prior is tight (HeightBiasOptions::scale_sigma0) and it moves
// little unless the ranges ask for it.
// Why its own 3-D position: the particle set is planar (core/filter/particle_set.hpp) and
// cannot carry 1 + 8 more dimensions. A first version fed these states with the planar
// filter's position as if known: the position had itself been pulled by the biased ranges,
// so a third of each bias stayed in it (sim drone seed 1: up to 0.13 m bias error, ATE
// 0.13 m). Here position and biases share one covariance, so the range geometry of a moving
// device separates them (a bias is the same at every pose, a position error is not; anchors
// at different heights see z with opposite signs dz / d). The planar filter stays the
// horizontal output; it takes z and the biases from here.
// NLOS: a blocked anchor's ranges are long (one-sided); an innovation beyond gate_sigma on
// either side is not used (and counted): on the long side it is NLOS, on the short side a
// range no LOS model explains. Per anchor, the share of recent long-gated ranges flags the
// anchor as in NLOS (innovation history, part 4).
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>

#include "core/common/time.hpp"

namespace luxloc {

struct HeightBiasOptions {
  bool estimate_height = false;
  bool estimate_bias = false;
  bool estimate_scale = false;  // with estimate_bias only: a scale state per anchor too
  // Priors. Position: around the first planar estimate, its covariance plus 0.5 m; height:
  // around the nominal device height, 0.5 m covers a drone's 0.5-1.7 m around 1.1 m at 1.2
  // sigma. Bias: 0.3 m covers the antenna delays of uncalibrated kits (issue 16: -0.44 ..
  // -0.02 m) at ~1.5 sigma; an anchor with a calib uwb bias keeps a 3 cm prior (calib uwb's
  // residual spread is < 2 cm).
  double position_sigma0_m = 0.5;
  double height_sigma0_m = 0.5;
  double speed_sigma0_mps = 0.5;
  double bias_sigma0_m = 0.3;
  double calibrated_bias_sigma0_m = 0.03;
  // White-acceleration psd ((m/s^2)^2 / Hz), horizontal and vertical: a robot's or drone's
  // turns of ~1 m/s^2, gentler climbs. On sim drone seeds 1-10 (docs/PLATFORMS.md) ATE is
  // flat over 0.3-3 (0.062-0.063 m) and z RMSE 0.058 / 0.060 / 0.063 m for 0.03 / 0.1 / 0.3:
  // 0.1 kept over the sim's best, which fits its gentle climb and would lag a real one.
  double horizontal_accel_psd = 1.0;
  double vertical_accel_psd = 0.1;
  // Bias random walk psd (m^2/s): 1e-5 lets a bias move ~2.5 cm a minute (temperature drift
  // of an antenna delay is slower); the filter then stays open to a wrong start.
  double bias_walk_psd = 1e-5;
  // Scale error prior (fraction): what low-cost kits show as a slope is up to 1-2 % (a
  // received-power bias that changes with distance; a clock offset alone is ~2e-5): 0.01.
  // After calib uwb --scale 0.003 (its spread on sim drone seeds with 1 % scales: within
  // 0.002). Random walk psd 1e-9 /s: a scale does not change within a run.
  double scale_sigma0 = 0.01;
  double calibrated_scale_sigma0 = 0.003;
  double scale_walk_psd = 1e-9;
  // Innovations beyond this many sigma are set aside (NLOS long, gross short): 3 sigma keeps
  // 99.7 % of LOS ranges.
  double gate_sigma = 3.0;
  // An anchor is flagged NLOS while the exponentially weighted share of its long-gated
  // ranges (weight nlos_memory per range: ~5 ranges, 0.5 s at 10 Hz) exceeds nlos_share.
  double nlos_memory = 0.2;
  double nlos_share = 0.5;
  // A short range cannot be NLOS (blockage only lengthens a path): a run of short-gated
  // ranges from one anchor means the filter's bias for it is wrong, and gating them would
  // keep it wrong for good (sim robot seed 8, a tuning seed: anchor 3 learnt +0.34 m against
  // a true -0.38 m and 881 ranges were set aside as short). After this many in a row (a LOS
  // range is 3 sigma short with p = 0.0013: 5 in a row never happen by chance; ~0.5 s at
  // 10 Hz) the anchor's bias variance is reopened to its prior and the range is used.
  int short_run_reopen = 5;
  double min_height_m = -1.0, max_height_m = 10.0;  // z is kept in this span (a diverged z stops here)
};

struct HeightBiasStats {
  std::uint64_t used = 0, gated_long = 0, gated_short = 0;
  std::uint64_t bias_reopened = 0;  // runs of short ranges that reopened an anchor's bias
  std::uint64_t heights_used = 0, heights_gated = 0;  // update_height
};

class HeightBiasFilter {
 public:
  HeightBiasFilter(const HeightBiasOptions& options, double nominal_height_m);

  // Adds an anchor's bias state (the calib uwb value, if any, already removed from the
  // ranges: prior 0 with the calibrated or the uncalibrated sigma). Known anchors: no-op.
  void add_anchor(int id, bool calibrated);
  // Starts the horizontal states at a planar estimate (its covariance plus the prior's).
  void start(TimeNs t, const Eigen::Vector2d& p_xy, const Eigen::Matrix2d& cov_xy);
  bool started() const { return t_.has_value(); }
  // Moves the states to time t (no-op before start() or for an older t).
  void predict(TimeNs t);
  enum class Outcome { used, gated_long, gated_short, skipped };
  // One range (calibration removed) to anchor `id` at a_inW, LOS noise range_sigma_m.
  Outcome update(int id, const Eigen::Vector3d& a_inW, double range_m, double range_sigma_m);

  // A direct height of the body (the camera geometry, core/vlc/camera_height.hpp) at the
  // filter's time: one height state for every source. Gated at gate_sigma; skipped unless
  // the height is estimated and the filter started.
  Outcome update_height(double z_m, double sigma_m);
  bool enabled() const { return options_.estimate_height || options_.estimate_bias; }
  // The nominal height until started or without height estimation.
  double height_m() const;
  double height_sigma_m() const;
  Eigen::Vector2d position_xy() const { return x_.head<2>(); }
  // The anchor's learnt bias (0 without a state) and its sigma (0 without a state).
  double bias_m(int id) const;
  // The anchor's learnt scale (1 + s; 1 without a state).
  double scale(int id) const;
  double scale_sigma(int id) const;  // 0 without a state
  // A range with the learnt bias and scale removed: (r - b) / (1 + s).
  double corrected(int id, double range_m) const { return (range_m - bias_m(id)) / scale(id); }
  double bias_sigma_m(int id) const;
  bool nlos(int id) const;
  const HeightBiasStats& stats() const { return stats_; }
  const HeightBiasOptions& options() const { return options_; }

 private:
  struct AnchorState {
    Eigen::Index k = 0;   // index of b in x_
    Eigen::Index ks = -1; // index of s in x_ (-1: no scale state)
    double long_share = 0.0;
    double sigma0_m = 0.0;  // the bias prior (calibrated or not)
    int short_run = 0;      // consecutive short-gated ranges
  };
  HeightBiasOptions options_;
  double nominal_height_m_;
  Eigen::VectorXd x_;  // [px, py, pz, vx, vy, vz, b...]
  Eigen::MatrixXd P_;
  std::map<int, AnchorState> anchors_;
  std::optional<TimeNs> t_;
  HeightBiasStats stats_;
};

}  // namespace luxloc
