#pragma once
// Position from ranges to >= 3 known anchors at a known device height (SEEDS.md A's S203
// trilateration, with measured 3-D distances): Gauss-Newton least squares on
//   e_i(x, y) = || (x, y, z_B) - a_i || - d_i,
// started from the linear solution (differences of the squared equations), with Huber
// reweighting so one NLOS range does not drag the solution; with >= 4 anchors and a poor
// fit, the leave-one-out subset that fits clearly best replaces it (one NLOS range
// identified). Covariance sigma^2 (J^T W J)^-1.
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
};

struct Multilateration {
  PositionMeasurement fix;
  double rms_m = 0.0;  // residual RMS
  int iterations = 0;
};

// nullopt for < 3 ranges, a degenerate geometry (collinear anchors) or no convergence.
std::optional<Multilateration> multilaterate(const std::vector<RangeToAnchor>& ranges, double z_B,
                                             const MultilaterationOptions& options = {});

}  // namespace luxloc
