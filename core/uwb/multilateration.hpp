#pragma once
// Position from ranges to >= 3 known anchors at a known device height (SEEDS.md A's S203
// trilateration, with measured 3-D distances): Gauss-Newton least squares on
//   e_i(x, y) = || (x, y, z_B) - a_i || - d_i,
// started from the linear solution (differences of the squared equations), with Huber
// reweighting so one NLOS range does not drag the solution; with >= 4 anchors and a poor
// fit, the leave-one-out subset that fits clearly best replaces it (one NLOS range
// identified). Covariance sigma^2 (J^T W J)^-1.
// Mirrors (issue 16 part 4): ranges from anchors on one side (a line of anchors, a corner)
// fit a point and its reflection equally well. A solution more than hull_margin_m outside
// the 2-D convex hull of all the anchors (`area`; empty: those of the ranges) is re-solved
// from starts inside it (the area's centroid and the solution reflected through it); a fit
// inside that is as good wins, and a solution that stays outside is flagged outside_hull
// (the callers say so). All the anchors, not the group's: staggered ranging groups 3-4
// neighbouring anchors, which a device elsewhere in the room is always outside of.
#include <optional>
#include <vector>

#include "core/filter/planar_filter.hpp"

namespace luxloc {

struct RangeToAnchor {
  Eigen::Vector3d p_AinW;
  double range_m = 0.0;
};

struct MultilaterationOptions {
  double range_sigma_m = 0.10;
  double huber_k = 2.0;   // residuals beyond k sigma are down-weighted (0: plain least squares)
  int max_iterations = 20;
  double max_rms_m = 1.0;  // a solution whose weighted residuals stay larger is refused
  // 1 m: a device beside the outer anchors (a drone past the wall anchors of a room) is
  // no mirror; a mirror through a wall of anchors lies metres out.
  double hull_margin_m = 1.0;
};

struct Multilateration {
  PositionMeasurement fix;
  double rms_m = 0.0;  // residual RMS
  int iterations = 0;
  bool outside_hull = false;  // more than hull_margin_m outside the anchors' hull (no better fit inside)
};

// nullopt for < 3 ranges, a degenerate geometry (collinear anchors) or no convergence.
std::optional<Multilateration> multilaterate(const std::vector<RangeToAnchor>& ranges, double z_B,
                                             const MultilaterationOptions& options = {},
                                             const std::vector<Eigen::Vector2d>& area = {});

}  // namespace luxloc
