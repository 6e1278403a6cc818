#include "core/uwb/range_bias_calibration.hpp"

#include <algorithm>
#include <cmath>

namespace luxloc {

RangeCalibration fit_range_calibration(const std::vector<RangePair>& pairs, const RangeCalibrationOptions& o) {
  RangeCalibration c;
  std::vector<bool> keep(pairs.size(), true);
  if (pairs.size() < o.min_ranges) return c;
  {
    // First cut, robust to a long one-sided NLOS tail (an anchor blocked for a third of the
    // run): centre at the 25 % quantile of measured - true, spread from the 5 %..25 % gap
    // (0.97 sigma for a Gaussian), keep +-trim_sigma of that.
    std::vector<double> r;
    for (const RangePair& p : pairs) r.push_back(p.measured_m - p.true_m);
    std::vector<double> q = r;
    std::sort(q.begin(), q.end());
    const double q25 = q[q.size() / 4], q05 = q[q.size() / 20];
    const double sigma = std::max(1e-3, (q25 - q05) / 0.97);
    for (std::size_t i = 0; i < r.size(); ++i) keep[i] = std::abs(r[i] - q25) <= o.trim_sigma * sigma;
  }
  for (int round = 0; round < o.rounds; ++round) {
    // Normal equations of measured = scale * true + bias over the kept ranges.
    double n = 0, st = 0, sm = 0, stt = 0, stm = 0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (!keep[i]) continue;
      n += 1;
      st += pairs[i].true_m;
      sm += pairs[i].measured_m;
      stt += pairs[i].true_m * pairs[i].true_m;
      stm += pairs[i].true_m * pairs[i].measured_m;
    }
    if (n < static_cast<double>(o.min_ranges)) return RangeCalibration{};
    const double det = n * stt - st * st;
    if (o.fit_scale && det > 1e-9 * n * n) {
      c.scale = (n * stm - st * sm) / det;
      c.bias_m = (sm - c.scale * st) / n;
    } else {
      c.scale = 1.0;
      c.bias_m = (sm - st) / n;
    }
    std::vector<double> abs_res;
    for (std::size_t i = 0; i < pairs.size(); ++i)
      abs_res.push_back(std::abs(pairs[i].measured_m - c.scale * pairs[i].true_m - c.bias_m));
    std::vector<double> sorted;
    for (std::size_t i = 0; i < pairs.size(); ++i)
      if (keep[i]) sorted.push_back(abs_res[i]);
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double sigma = std::max(1e-4, 1.4826 * sorted[sorted.size() / 2]);
    c.used = c.trimmed = 0;
    double ss = 0.0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      keep[i] = abs_res[i] <= o.trim_sigma * sigma;
      if (keep[i]) {
        ++c.used;
        ss += abs_res[i] * abs_res[i];
      } else {
        ++c.trimmed;
      }
    }
    c.residual_sigma_m = c.used ? std::sqrt(ss / static_cast<double>(c.used)) : 0.0;
  }
  c.valid = true;
  return c;
}

}  // namespace luxloc
