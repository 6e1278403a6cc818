#pragma once
// Sub-row estimation of the period of rolling-shutter stripes from a per-row intensity
// profile (SEEDS.md A, S202/S203: "count the stripes" done as a frequency estimate).
//
// Method: a weighted least-squares periodogram (a sinusoid plus a low-order polynomial
// trend is fitted at each trial frequency; the power is the variance the sinusoid
// explains) on a fine grid over [1/max_period, 1/min_period], golden-section refinement
// of the peak, then a sub-harmonic check so that the 2nd / 3rd harmonic of a square wave
// is never taken for its fundamental.
#include <span>
#include <vector>

namespace luxloc {

struct StripePeriodOptions {
  int trend_order = 1;             // polynomial trend fitted with the sinusoid (0..2)
  double grid_oversampling = 6.0;  // grid step = 1 / (oversampling * profile length) cycles/row
  int max_subharmonic = 3;         // test nu/2 .. nu/k as the possible fundamental
  // A sub-harmonic nu/k inside the search range that explains at least this fraction of
  // the peak's power is taken as the fundamental (a square wave's 3rd harmonic carries
  // <= 1/9 of the fundamental's power, its 2nd none at 50 % duty).
  double subharmonic_power_ratio = 0.25;
};

struct StripePeriodEstimate {
  bool valid = false;
  double period_rows = 0.0;     // stripe period in rows (sub-row precision)
  double cycles_per_row = 0.0;  // 1 / period_rows
  double explained = 0.0;       // fraction of the detrended variance the sinusoid explains, 0..1
  double peak_to_sidelobe = 0.0;  // peak power / largest power away from the peak and its harmonics
  double period_sigma_rows = 0.0;  // 1-sigma from the residual (Cramer-Rao for a sinusoid in white noise)
  double amplitude = 0.0;       // sinusoid amplitude, profile units
  double phase_rad = 0.0;       // profile ~ trend + amplitude * cos(2 pi v / period - phase)
  double span_rows = 0.0;       // rows between the first and last sample with weight > 0
  int subharmonic = 1;          // k when the global peak was the k-th harmonic of the result
  bool at_range_edge = false;   // refined peak on the boundary of the search range
};

// `profile[v]` is the mean intensity of row v; `weights[v]` >= 0 its weight (0 = no data;
// empty = all 1). Periods are searched in [min_period, max_period] rows.
StripePeriodEstimate estimate_stripe_period(std::span<const double> profile, std::span<const double> weights,
                                            double min_period, double max_period,
                                            const StripePeriodOptions& options = {});

inline StripePeriodEstimate estimate_stripe_period(const std::vector<double>& row_profile, double min_period,
                                                   double max_period, const StripePeriodOptions& options = {}) {
  return estimate_stripe_period(std::span<const double>(row_profile), std::span<const double>(), min_period,
                                max_period, options);
}

// Period from the stripe edges, for blobs too short for the periodogram (fewer than ~2
// periods: there the square wave's harmonics bias a sinusoid fit). A rolling-shutter
// stripe is the LED's square wave box-filtered by the exposure, so its half-level crossings
// keep the square wave's spacing: same-polarity edges are one period apart, a bright stripe
// is duty x period wide and a dark one (1 - duty) x period. Edges are found with
// hysteresis (35 % / 65 % of the profile's range) and placed at the 50 % crossing with
// sub-row interpolation; edges within `end_margin_rows` of the profile's ends (the disc's
// own blurred rim) are not used. Needs two interior edges (one whole stripe); with three or
// more, the same-polarity spacings must agree within 10 %; and the stripes before the first
// and after the last edge must not outlast their width (an edge predicted well inside the
// profile must have been found).
struct EdgePeriodEstimate {
  bool valid = false;
  double period_rows = 0.0;
  double period_sigma_rows = 0.0;  // from an edge position error of edge_sigma_rows
  int edges = 0;
};
EdgePeriodEstimate estimate_period_from_edges(std::span<const double> profile, std::span<const double> weights,
                                              double duty, double min_period, double max_period,
                                              double end_margin_rows = 3.0, double edge_sigma_rows = 0.25);

}  // namespace luxloc
