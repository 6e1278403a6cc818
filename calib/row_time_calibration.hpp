#pragma once
// `luxloc calib rowtime`: the rolling-shutter row (line readout) time of a camera mode,
// measured from one LED blinking at a known frequency (SEEDS.md A, S202 turned round:
// row_time = 1 / (f * stripe_period_rows)). FIELD_NOTES: the row time changes with the mode
// (scaling, binning, frame rate), so measure it per mode; camera.yaml's row_time_us is what
// the stripe decoder turns periods into frequencies with.
//
// Per frame: background (a low quantile), noise and threshold (frame_levels); the lit columns (those with
// at least `min_column_share` of the busiest column's lit pixels, the contiguous run around
// it: one light, or one large diffuser filling the frame); the rows from the first to the
// last lit row; the mean of the run's central `core_fraction` of columns per row is the
// stripe profile; its period by estimate_stripe_period (sinusoid + quadratic trend for the
// disc's envelope, sub-harmonic check) over the periods the row-time range allows. A frame
// counts when the profile holds >= min_periods stripe periods and the fit explains enough
// of it; the result is the median over the frames that count, with a MAD spread.
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace luxloc::calib {

struct RowTimeOptions {
  double led_freq_hz = 0.0;  // the LED's blink frequency (required)
  double min_row_time_us = 3.0;  // search range (FIELD_NOTES: ~15 us at 1080p on a phone, 30-45 us on webcams)
  double max_row_time_us = 150.0;
  double min_contrast_dn = 16.0;  // lit: background + max(min_contrast_dn, threshold_sigma * noise)
  double threshold_sigma = 6.0;
  // The background is this quantile of the frame: low, since the light may fill the frame
  // (its dark stripes are then the background).
  double background_quantile = 0.05;
  double min_column_share = 0.2;
  double core_fraction = 0.6;
  int min_rows = 16;
  double min_periods = 2.5;      // fewer stripe periods in the lit rows: the period is not trusted
  double min_explained = 0.3;    // periodic share of the profile's variance
  double min_peak_to_sidelobe = 1.5;
};

struct RowTimeFrame {
  bool valid = false;
  std::string reason;  // why not, when !valid
  double row_time_s = 0.0;
  double row_time_sigma_s = 0.0;
  double period_rows = 0.0;
  double periods = 0.0;  // stripe periods across the profile
  double explained = 0.0;
  int first_row = 0, last_row = -1, first_col = 0, last_col = -1;
};

// `gray`: CV_8UC1 (CV_8UC3 / CV_8UC4 BGR(A) and CV_16UC1 are converted: as_gray8). Throws std::invalid_argument on
// options without a frequency or with an empty row-time range.
RowTimeFrame measure_row_time(const cv::Mat& gray, const RowTimeOptions& options);

struct RowTimeSummary {
  int frames = 0, used = 0;
  double row_time_s = 0.0;     // median over the frames used
  double spread_s = 0.0;       // 1.4826 x MAD over them (0 with one frame)
  double min_s = 0.0, max_s = 0.0;
};
RowTimeSummary summarize_row_times(const std::vector<RowTimeFrame>& frames);

}  // namespace luxloc::calib
