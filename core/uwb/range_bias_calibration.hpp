#pragma once
// Offline per-anchor range calibration (issue 16 part 2, `luxloc calib uwb`): from ranges
// whose true distance is known (a session with ground truth), fit per anchor
//   measured = scale * true + bias                      (linear least squares, 2 unknowns)
// trimmed: a first cut around the 25 % quantile of measured - true (NLOS only lengthens
// ranges), then after each fit ranges whose residual exceeds trim_sigma robust sigmas
// (1.4826 MAD) are left out and the fit is redone, so NLOS ranges (long, one-sided) do not
// pull the bias. With fit_scale false only the bias is fitted (scale 1: median-free mean
// of the kept residuals).
#include <vector>

namespace luxloc {

struct RangePair {
  double measured_m = 0.0;
  double true_m = 0.0;
};

struct RangeCalibrationOptions {
  bool fit_scale = false;  // a 3-8 m span pins a scale to ~1e-3 only; the bias is what kits need
  // 3 robust sigmas, 4 rounds: on sim seeds 1-10 the drone's blocked-anchor bias settled
  // within 1 mm after 3 rounds.
  double trim_sigma = 3.0;
  int rounds = 4;
  std::size_t min_ranges = 20;
};

struct RangeCalibration {
  bool valid = false;
  double bias_m = 0.0, scale = 1.0;
  double residual_sigma_m = 0.0;  // of the kept ranges
  std::size_t used = 0, trimmed = 0;
};

RangeCalibration fit_range_calibration(const std::vector<RangePair>& pairs, const RangeCalibrationOptions& options = {});

}  // namespace luxloc
