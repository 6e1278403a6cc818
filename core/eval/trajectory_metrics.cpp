#include "core/eval/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace luxloc {
namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

double rad_to_deg(double a) { return a * 180.0 / std::numbers::pi; }

}  // namespace

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);  // [-pi, pi]
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(pos));
  if (i + 1 >= v.size()) return v.back();
  return v[i] + (pos - static_cast<double>(i)) * (v[i + 1] - v[i]);
}

bool interpolate_truth(const std::vector<TruthRow>& truth, TimeNs t, TruthRow& out) {
  if (truth.empty() || t < truth.front().t || t > truth.back().t) return false;
  auto hi = std::lower_bound(truth.begin(), truth.end(), t, [](const TruthRow& r, TimeNs x) { return r.t < x; });
  if (hi->t == t) {
    out = *hi;
    return true;
  }
  const TruthRow& b = *hi;
  const TruthRow& a = *(hi - 1);
  const double f = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  out.t = t;
  out.p_inW = a.p_inW + f * (b.p_inW - a.p_inW);
  out.yaw = (std::isfinite(a.yaw) && std::isfinite(b.yaw)) ? wrap_angle(a.yaw + f * wrap_angle(b.yaw - a.yaw))
                                                           : std::numeric_limits<double>::quiet_NaN();
  return true;
}

EvalResult evaluate(const std::vector<TruthRow>& truth, const std::vector<PoseRow>& poses,
                    const EvalOptions& options) {
  if (truth.size() < 2) throw std::invalid_argument("evaluate: ground truth needs at least 2 rows");
  for (std::size_t i = 1; i < truth.size(); ++i)
    if (truth[i].t <= truth[i - 1].t) throw std::invalid_argument("evaluate: truth not in increasing time order");
  if (!(options.coverage_bin_s > 0.0)) throw std::invalid_argument("evaluate: coverage_bin_s must be > 0");

  EvalResult r;
  r.truth_t0 = truth.front().t;
  r.truth_t1 = truth.back().t;
  r.coverage_bin_s = options.coverage_bin_s;

  std::vector<const PoseRow*> sorted;
  sorted.reserve(poses.size());
  for (const PoseRow& p : poses) sorted.push_back(&p);
  std::stable_sort(sorted.begin(), sorted.end(), [](const PoseRow* a, const PoseRow* b) { return a->t < b->t; });

  std::vector<double> err, yaw_abs;
  double yaw_sq = 0.0, sigma_sum = 0.0, z_sq = 0.0;
  std::size_t inside = 0, inside_yaw = 0, inside_z = 0, n_z = 0;
  for (const PoseRow* p : sorted) {
    TruthRow g;
    if (!interpolate_truth(truth, p->t, g)) {
      ++r.n_outside;
      continue;
    }
    PoseError e;
    e.t = p->t;
    e.p_est = p->p_inW.head<2>();
    e.p_truth = g.p_inW.head<2>();
    e.err_m = (e.p_est - e.p_truth).norm();
    if (std::isfinite(p->yaw) && std::isfinite(g.yaw)) {
      e.yaw_err_rad = wrap_angle(p->yaw - g.yaw);
      yaw_sq += e.yaw_err_rad * e.yaw_err_rad;
      yaw_abs.push_back(std::abs(e.yaw_err_rad));
      ++r.n_yaw;
      if (std::isfinite(p->sigma_yaw) && p->sigma_yaw > 0.0) {
        e.yaw_z = std::abs(e.yaw_err_rad) / p->sigma_yaw;
        ++r.n_sigma_yaw;
        if (e.yaw_z <= 1.96) ++inside_yaw;
      }
    }
    if (std::isfinite(p->sigma_x) && std::isfinite(p->sigma_y) && p->sigma_x > 0.0 && p->sigma_y > 0.0) {
      const Eigen::Vector2d d = e.p_est - e.p_truth;
      e.mahalanobis2 = d.x() * d.x() / (p->sigma_x * p->sigma_x) + d.y() * d.y() / (p->sigma_y * p->sigma_y);
      ++r.n_sigma;
      if (e.mahalanobis2 <= 5.991) ++inside;
      sigma_sum += std::sqrt(0.5 * (p->sigma_x * p->sigma_x + p->sigma_y * p->sigma_y));
    }
    if (const double ez = p->p_inW.z() - g.p_inW.z(); std::isfinite(ez)) {
      z_sq += ez * ez;
      ++n_z;
      if (std::isfinite(p->sigma_z) && p->sigma_z > 0.0) {
        ++r.n_sigma_z;
        if (std::abs(ez) <= 1.96 * p->sigma_z) ++inside_z;
      }
    }
    err.push_back(e.err_m);
    r.errors.push_back(e);
  }
  r.n = r.errors.size();
  if (r.n_yaw > 0) {
    r.yaw_rmse_rad = std::sqrt(yaw_sq / static_cast<double>(r.n_yaw));
    r.yaw_p50_rad = percentile(yaw_abs, 0.5);
    r.yaw_p95_rad = percentile(yaw_abs, 0.95);
    r.yaw_max_rad = *std::max_element(yaw_abs.begin(), yaw_abs.end());
  }
  if (r.n_sigma > 0) {
    r.consistency = static_cast<double>(inside) / static_cast<double>(r.n_sigma);
    r.mean_sigma_m = sigma_sum / static_cast<double>(r.n_sigma);
  }
  if (r.n_sigma_yaw > 0) r.yaw_consistency = static_cast<double>(inside_yaw) / static_cast<double>(r.n_sigma_yaw);
  if (n_z > 0) r.z_rmse_m = std::sqrt(z_sq / static_cast<double>(n_z));
  if (r.n_sigma_z > 0) r.z_consistency = static_cast<double>(inside_z) / static_cast<double>(r.n_sigma_z);

  // Coverage (kCoverageDefinition): length-weighted share of covered bins.
  const double span = ns_to_seconds(r.truth_t1 - r.truth_t0);
  const double bin = options.coverage_bin_s;
  const auto n_bins = static_cast<std::size_t>(std::max(1.0, std::ceil(span / bin - 1e-9)));
  std::vector<char> covered(n_bins, 0);
  for (const PoseError& e : r.errors) {
    const double dt = ns_to_seconds(e.t - r.truth_t0);
    covered[std::min(n_bins - 1, static_cast<std::size_t>(std::floor(dt / bin)))] = 1;
  }
  double covered_s = 0.0;
  for (std::size_t i = 0; i < n_bins; ++i)
    if (covered[i]) covered_s += std::min(bin, span - static_cast<double>(i) * bin);
  r.coverage = std::clamp(covered_s / span, 0.0, 1.0);

  if (r.n == 0) return r;
  double sq = 0.0, sum = 0.0;
  r.max_m = -1.0;
  for (const PoseError& e : r.errors) {
    sq += e.err_m * e.err_m;
    sum += e.err_m;
    if (e.err_m > r.max_m) {
      r.max_m = e.err_m;
      r.t_max = e.t;
    }
  }
  r.rmse_m = std::sqrt(sq / static_cast<double>(r.n));
  r.mean_m = sum / static_cast<double>(r.n);
  r.median_m = percentile(err, 0.5);
  r.p95_m = percentile(err, 0.95);
  return r;
}

std::string format_eval_summary(const EvalResult& r) {
  std::string s;
  if (r.n == 0) {
    s = "ATE RMSE - | n 0 | coverage 0.0 %";
  } else {
    s = "ATE RMSE " + fmt("%.3f", r.rmse_m) + " m | median " + fmt("%.3f", r.median_m) + " | p95 " +
        fmt("%.3f", r.p95_m) + " | max " + fmt("%.3f", r.max_m) + " | n " + std::to_string(r.n) +
        " | coverage " + fmt("%.1f", 100.0 * r.coverage) + " %";
  }
  if (r.n_yaw > 0)
    s += " | yaw RMSE " + fmt("%.2f", rad_to_deg(r.yaw_rmse_rad)) + " deg, p95 " + fmt("%.2f", rad_to_deg(r.yaw_p95_rad));
  if (r.n_sigma > 0) s += " | within 95 % " + fmt("%.1f", 100.0 * r.consistency) + " %";
  return s;
}

double settle_time_s(const EvalResult& r, double limit_m) {
  double t = std::numeric_limits<double>::quiet_NaN();
  for (auto it = r.errors.rbegin(); it != r.errors.rend(); ++it) {
    if (!(it->err_m < limit_m)) break;
    t = ns_to_seconds(it->t);
  }
  return t;
}

std::string format_eval_report(const EvalResult& r) {
  std::string s;
  const double t0 = ns_to_seconds(r.truth_t0), t1 = ns_to_seconds(r.truth_t1);
  s += "truth span       " + fmt("%.3f", t0) + " .. " + fmt("%.3f", t1) + " s (" + fmt("%.3f", t1 - t0) + " s)\n";
  s += "poses evaluated  " + std::to_string(r.n) + " (" + std::to_string(r.n_outside) +
       " outside the truth span, ignored)\n";
  s += "coverage         " + fmt("%.1f", 100.0 * r.coverage) + " % (" + fmt("%g", r.coverage_bin_s) +
       "-s bins of the truth span holding a pose)\n";
  if (r.n > 0) {
    s += "horizontal (x, y) error, no alignment:\n";
    s += "  ATE RMSE       " + fmt("%.4f", r.rmse_m) + " m\n";
    s += "  mean           " + fmt("%.4f", r.mean_m) + " m\n";
    s += "  median         " + fmt("%.4f", r.median_m) + " m\n";
    s += "  p95            " + fmt("%.4f", r.p95_m) + " m\n";
    s += "  max            " + fmt("%.4f", r.max_m) + " m at t = " + fmt("%.3f", ns_to_seconds(r.t_max)) + " s\n";
  }
  if (r.n_yaw > 0)
    s += "yaw RMSE         " + fmt("%.4f", r.yaw_rmse_rad) + " rad (" + fmt("%.2f", rad_to_deg(r.yaw_rmse_rad)) +
         " deg) over " + std::to_string(r.n_yaw) + " poses\n";
  else
    s += "yaw RMSE         - (the estimate or the truth has no yaw)\n";
  if (r.n_yaw > 0)
    s += "yaw |error|      p50 " + fmt("%.2f", rad_to_deg(r.yaw_p50_rad)) + " deg, p95 " +
         fmt("%.2f", rad_to_deg(r.yaw_p95_rad)) + " deg, max " + fmt("%.2f", rad_to_deg(r.yaw_max_rad)) + " deg\n";
  if (r.n_sigma > 0)
    s += "sigma            " + fmt("%.1f", 100.0 * r.consistency) +
         " % of the poses within their 95 % ellipse (an honest sigma: ~95 %), mean sigma " +
         fmt("%.4f", r.mean_sigma_m) + " m over " + std::to_string(r.n_sigma) + " poses\n";
  if (r.n_sigma_yaw > 0)
    s += "sigma_yaw        " + fmt("%.1f", 100.0 * r.yaw_consistency) + " % of the poses within 1.96 sigma_yaw\n";
  if (std::isfinite(r.z_rmse_m))
    s += "z RMSE           " + fmt("%.4f", r.z_rmse_m) + " m" +
         (r.n_sigma_z > 0 ? ", " + fmt("%.1f", 100.0 * r.z_consistency) + " % within 1.96 sigma_z" : std::string()) + "\n";
  s += format_eval_summary(r) + "\n";
  return s;
}

std::string format_eval_json(const EvalResult& r) {
  std::string s = "{";
  auto add = [&s](const char* key, const std::string& v) {
    if (v.empty()) return;
    if (s.size() > 1) s += ',';
    s += '"';
    s += key;
    s += "\":";
    s += v;
  };
  auto num = [](double v, const char* f) { return std::isfinite(v) ? fmt(f, v) : std::string(); };
  add("n", std::to_string(r.n));
  add("n_outside", std::to_string(r.n_outside));
  add("coverage", num(r.coverage, "%.6f"));
  add("coverage_bin_s", num(r.coverage_bin_s, "%g"));
  add("truth_t0", num(ns_to_seconds(r.truth_t0), "%.6f"));
  add("truth_t1", num(ns_to_seconds(r.truth_t1), "%.6f"));
  add("ate_rmse_m", num(r.rmse_m, "%.6f"));
  add("mean_m", num(r.mean_m, "%.6f"));
  add("median_m", num(r.median_m, "%.6f"));
  add("p95_m", num(r.p95_m, "%.6f"));
  add("max_m", num(r.max_m, "%.6f"));
  if (r.n > 0) add("t_max", num(ns_to_seconds(r.t_max), "%.6f"));
  add("n_yaw", std::to_string(r.n_yaw));
  add("yaw_rmse_rad", num(r.yaw_rmse_rad, "%.6f"));
  add("yaw_p50_rad", num(r.yaw_p50_rad, "%.6f"));
  add("yaw_p95_rad", num(r.yaw_p95_rad, "%.6f"));
  add("yaw_max_rad", num(r.yaw_max_rad, "%.6f"));
  add("n_sigma", std::to_string(r.n_sigma));
  add("consistency", num(r.consistency, "%.6f"));
  add("mean_sigma_m", num(r.mean_sigma_m, "%.6f"));
  add("n_sigma_yaw", std::to_string(r.n_sigma_yaw));
  add("yaw_consistency", num(r.yaw_consistency, "%.6f"));
  add("z_rmse_m", num(r.z_rmse_m, "%.6f"));
  add("n_sigma_z", std::to_string(r.n_sigma_z));
  add("z_consistency", num(r.z_consistency, "%.6f"));
  s += '}';
  return s;
}

}  // namespace luxloc
