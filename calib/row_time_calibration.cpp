#include "calib/row_time_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/vlc/frame_levels.hpp"
#include "core/vlc/stripe_period.hpp"

namespace luxloc::calib {

RowTimeFrame measure_row_time(const cv::Mat& input, const RowTimeOptions& o) {
  if (!(o.led_freq_hz > 0.0)) throw std::invalid_argument("the LED frequency must be > 0 Hz");
  if (!(o.min_row_time_us > 0.0) || !(o.max_row_time_us > o.min_row_time_us))
    throw std::invalid_argument("the row-time range must satisfy 0 < min < max");
  RowTimeFrame out;
  cv::Mat buffer;
  const cv::Mat* gp = as_gray8(input, buffer);
  if (!gp) {
    out.reason = "unsupported pixel format";
    return out;
  }
  const cv::Mat& gray = *gp;
  if (gray.empty()) {
    out.reason = "empty frame";
    return out;
  }
  const FrameLevels lv = frame_levels(gray, o.min_contrast_dn, o.threshold_sigma, o.background_quantile);
  // The lit columns: a contiguous run around the busiest column.
  std::vector<int> col_count(static_cast<std::size_t>(gray.cols), 0);
  for (int r = 0; r < gray.rows; ++r) {
    const uchar* p = gray.ptr<uchar>(r);
    for (int c = 0; c < gray.cols; ++c) col_count[static_cast<std::size_t>(c)] += p[c] > lv.threshold ? 1 : 0;
  }
  const auto busiest = std::max_element(col_count.begin(), col_count.end());
  if (*busiest < 2) {
    out.reason = "no light above the background";
    return out;
  }
  const int need = std::max(1, static_cast<int>(std::ceil(o.min_column_share * *busiest)));
  int c0 = static_cast<int>(busiest - col_count.begin()), c1 = c0;
  while (c0 > 0 && col_count[static_cast<std::size_t>(c0 - 1)] >= need) --c0;
  while (c1 + 1 < gray.cols && col_count[static_cast<std::size_t>(c1 + 1)] >= need) ++c1;
  const double mid = 0.5 * (c0 + c1), half = 0.5 * (c1 - c0 + 1) * o.core_fraction;
  const int k0 = std::max(c0, static_cast<int>(std::lround(mid - half)));
  const int k1 = std::min(c1, std::max(k0, static_cast<int>(std::lround(mid + half))));
  // Rows from the first to the last lit row of the core columns.
  int r0 = -1, r1 = -1;
  std::vector<double> profile(static_cast<std::size_t>(gray.rows), 0.0);
  for (int r = 0; r < gray.rows; ++r) {
    const uchar* p = gray.ptr<uchar>(r);
    double sum = 0.0;
    bool lit = false;
    for (int c = k0; c <= k1; ++c) {
      sum += p[c];
      lit = lit || p[c] > lv.threshold;
    }
    profile[static_cast<std::size_t>(r)] = sum / (k1 - k0 + 1) - lv.background;
    if (lit) {
      if (r0 < 0) r0 = r;
      r1 = r;
    }
  }
  out.first_col = c0;
  out.last_col = c1;
  out.first_row = r0;
  out.last_row = r1;
  if (r0 < 0 || r1 - r0 + 1 < o.min_rows) {
    out.reason = "too few lit rows";
    return out;
  }
  const std::vector<double> rows(profile.begin() + r0, profile.begin() + r1 + 1);
  const double rt_lo = o.min_row_time_us * 1e-6, rt_hi = o.max_row_time_us * 1e-6;
  const double p_min = std::max(2.0, 1.0 / (o.led_freq_hz * rt_hi));
  const double p_max = std::min(static_cast<double>(rows.size()), 1.0 / (o.led_freq_hz * rt_lo));
  if (!(p_max > p_min)) {
    out.reason = "the lit rows are shorter than the shortest period the row-time range allows";
    return out;
  }
  StripePeriodOptions po;
  po.trend_order = 2;  // the disc's (or the diffuser's) envelope over the rows
  const StripePeriodEstimate e = estimate_stripe_period(rows, p_min, p_max, po);
  if (!e.valid) {
    out.reason = "no stripes";
    return out;
  }
  out.period_rows = e.period_rows;
  out.periods = e.span_rows / e.period_rows;
  out.explained = e.explained;
  out.row_time_s = 1.0 / (o.led_freq_hz * e.period_rows);
  out.row_time_sigma_s = out.row_time_s * e.period_sigma_rows / e.period_rows;
  if (e.explained < o.min_explained)
    out.reason = "no stripes";
  else if (out.periods < o.min_periods)
    out.reason = "too few stripe periods (bring the light closer or use a lower frequency)";
  else if (e.at_range_edge)
    out.reason = "period at the edge of the row-time range";
  else if (e.peak_to_sidelobe < o.min_peak_to_sidelobe)
    out.reason = "ambiguous period";
  else
    out.valid = true;
  return out;
}

RowTimeSummary summarize_row_times(const std::vector<RowTimeFrame>& frames) {
  RowTimeSummary s;
  s.frames = static_cast<int>(frames.size());
  std::vector<double> v;
  for (const RowTimeFrame& f : frames)
    if (f.valid) v.push_back(f.row_time_s);
  s.used = static_cast<int>(v.size());
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const auto median = [](std::vector<double> x) {
    const std::size_t n = x.size();
    std::nth_element(x.begin(), x.begin() + static_cast<long>(n / 2), x.end());
    double m = x[n / 2];
    if (n % 2 == 0) m = 0.5 * (m + *std::max_element(x.begin(), x.begin() + static_cast<long>(n / 2)));
    return m;
  };
  s.row_time_s = median(v);
  std::vector<double> dev;
  for (double x : v) dev.push_back(std::abs(x - s.row_time_s));
  s.spread_s = v.size() > 1 ? 1.4826 * median(dev) : 0.0;
  s.min_s = v.front();
  s.max_s = v.back();
  return s;
}

}  // namespace luxloc::calib
